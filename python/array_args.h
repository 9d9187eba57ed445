#pragma once
// Floating-point arrays from Python as the module takes them (an observation, an action, a vector env's actions):
// checked here, once, so that any other value — not a numpy array, integers, another shape, NaN or infinity — is a
// ValueError naming the argument, never a crash or a walker stepped with it.

#include <pybind11/pybind11.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

namespace poet::python {

// A numpy array of floating-point dtype, of exactly `shape`, every element finite: its elements as doubles in C
// order. Else std::invalid_argument (ValueError) naming `what`, its shape and, for a value not finite, its index.
std::vector<double> finite_array(const pybind11::handle& value, const char* what,
                                 const std::vector<pybind11::ssize_t>& shape);

// An array of shape (N,), as finite_array checks it.
template <size_t N>
std::array<double, N> finite_vector(const pybind11::handle& value, const char* what) {
  const std::vector<double> flat = finite_array(value, what, {static_cast<pybind11::ssize_t>(N)});
  std::array<double, N> out{};
  std::copy(flat.begin(), flat.end(), out.begin());
  return out;
}

// An array of shape (rows, N), as finite_array checks it, one std::array a row.
template <size_t N>
std::vector<std::array<double, N>> finite_rows(const pybind11::handle& value, const char* what, size_t rows) {
  const std::vector<double> flat =
      finite_array(value, what, {static_cast<pybind11::ssize_t>(rows), static_cast<pybind11::ssize_t>(N)});
  std::vector<std::array<double, N>> out(rows);
  for (size_t i = 0; i < rows; ++i) std::copy_n(flat.begin() + static_cast<std::ptrdiff_t>(i * N), N, out[i].begin());
  return out;
}

}  // namespace poet::python
