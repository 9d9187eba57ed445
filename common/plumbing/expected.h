#pragma once
// A value or an error message: the result type for recoverable errors at a boundary (parsing a file, a message),
// where the message names what was wrong. A small stand-in for C++23's std::expected<T, std::string>, which
// g++ 12 lacks. Build an error with `return Unexpected{"seed: not an integer"};`, a value by returning it.

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace poet {

// The error alternative, so that constructing an Expected<std::string> is never ambiguous.
struct Unexpected {
  std::string message;
};

template <class T>
class Expected {
 public:
  Expected(T value) : state_(std::in_place_index<0>, std::move(value)) {}                   // NOLINT: implicit
  Expected(Unexpected error) : state_(std::in_place_index<1>, std::move(error.message)) {}  // NOLINT: implicit

  bool has_value() const { return state_.index() == 0; }
  explicit operator bool() const { return has_value(); }

  // The value; throws std::logic_error (carrying the error message) when there is none: reading a value
  // without checking is a caller's bug, not an input error.
  T& value() & {
    check();
    return std::get<0>(state_);
  }
  const T& value() const& {
    check();
    return std::get<0>(state_);
  }
  T&& value() && {
    check();
    return std::get<0>(std::move(state_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  // The error message; empty when there is a value (so it can be logged either way).
  const std::string& error() const {
    static const std::string kNone;
    return has_value() ? kNone : std::get<1>(state_);
  }

 private:
  void check() const {
    if (!has_value()) throw std::logic_error("Expected::value() on an error: " + std::get<1>(state_));
  }

  std::variant<T, std::string> state_;
};

}  // namespace poet
