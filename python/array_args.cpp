#include "python/array_args.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace poet::python {
namespace {

namespace py = pybind11;

// A shape as Python prints it: "(4,)", "(2, 4)".
std::string shape_text(const std::vector<py::ssize_t>& shape) { return std::string(py::str(py::tuple(py::cast(shape)))); }

// The index of the flat element `at` in an array of `shape`, as Python writes it: "3", "1, 2".
std::string index_text(size_t at, const std::vector<py::ssize_t>& shape) {
  std::string text;
  for (size_t d = shape.size(); d-- > 0;) {
    const auto extent = static_cast<size_t>(shape[d]);
    text = std::to_string(at % extent) + (text.empty() ? "" : ", ") + text;
    at /= extent;
  }
  return text;
}

}  // namespace

std::vector<double> finite_array(const py::handle& value, const char* what, const std::vector<py::ssize_t>& shape) {
  if (!py::isinstance<py::array>(value))
    throw std::invalid_argument(std::string(what) + " must be a numpy array of shape " + shape_text(shape));
  const py::array array = py::reinterpret_borrow<py::array>(value);
  if (array.dtype().kind() != 'f')
    throw std::invalid_argument(std::string(what) + " must hold floating-point numbers, got dtype " +
                                std::string(py::str(array.dtype())));
  const std::vector<py::ssize_t> got(array.shape(), array.shape() + array.ndim());
  if (got != shape)
    throw std::invalid_argument(std::string(what) + " must have shape " + shape_text(shape) + ", got " +
                                shape_text(got));
  const auto doubles = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  std::vector<double> out(doubles.data(), doubles.data() + doubles.size());
  for (size_t i = 0; i < out.size(); ++i)
    if (!std::isfinite(out[i])) throw std::invalid_argument(std::string(what) + "[" + index_text(i, shape) + "] is not finite");
  return out;
}

}  // namespace poet::python
