#include "int_args.h"

#include <stdexcept>

namespace poet::python {

std::string int_text(const pybind11::int_& value) {
  // Python refuses to print an int of more than 4300 digits; a message needs no more than its size
  const auto bits = value.attr("bit_length")().cast<int64_t>();
  if (bits > 256)
    return std::string(value < pybind11::int_(0) ? "minus " : "") + "an integer of " + std::to_string(bits) + " bits";
  return std::string(pybind11::str(static_cast<const pybind11::handle&>(value)));
}

int64_t int_in_range(const pybind11::int_& value, int64_t lo, int64_t hi, const std::string& name) {
  if (value < pybind11::int_(lo) || value > pybind11::int_(hi))
    throw std::invalid_argument(name + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                int_text(value));
  return value.cast<int64_t>();
}

}  // namespace poet::python
