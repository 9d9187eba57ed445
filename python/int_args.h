#pragma once
// Integers from Python as the module takes them: a Python int of any size, checked against its range here, so that
// a value past what C++ holds (2**63, 2**200) is the module's ValueError naming the argument and its range, not
// pybind11's TypeError listing signatures.

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

namespace poet::python {

// value in [lo, hi], else std::invalid_argument (ValueError): "NAME must be in [LO, HI], got VALUE".
int64_t int_in_range(const pybind11::int_& value, int64_t lo, int64_t hi, const std::string& name);

// A Python int as a message shows it: its digits, or its size in bits when it has too many to print.
std::string int_text(const pybind11::int_& value);

}  // namespace poet::python
