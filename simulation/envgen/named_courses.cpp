#include "simulation/envgen/named_courses.h"

#include <array>

namespace poet {

namespace {

using namespace std::string_view_literals;

constexpr std::array kNames = {"flat"sv, "r1"sv, "r3"sv, "hard"sv, "hardcore-like"sv};

EnvEncoding make(std::string_view name, double roughness) {
  EnvEncoding e;
  e.name = std::string(name);
  e.roughness = roughness;
  return e;
}

}  // namespace

std::optional<EnvEncoding> named_course(std::string_view name) {
  if (name == "flat") return make(name, 0.0);
  if (name == "r1") return make(name, 1.0);
  if (name == "r3") return make(name, 3.0);
  if (name == "hard") {
    // stumps up to 2.5 meet one Table 1 condition: "challenging"
    EnvEncoding e = make(name, 3.0);
    e.pit_gap = Interval{2.0, 4.0};
    e.stump_width = Interval{1.0, 2.0};
    e.stump_height = Interval{1.5, 2.5};
    e.stump_float = Interval{0.0, 1.0};
    return e;
  }
  if (name == "hardcore-like") {
    // close to Gym's BipedalWalkerHardcore: every obstacle type, stumps up to 2, gaps up to 3, real stairs
    EnvEncoding e = make(name, 1.0);
    e.pit_gap = Interval{1.0, 3.0};
    e.stump_width = Interval{1.0, 3.0};
    e.stump_height = Interval{0.5, 2.0};
    e.stump_float = Interval{0.0, 1.0};
    e.stair_height = Interval{1.0, 1.0};
    e.stair_width = Interval{4.0, 5.0};
    e.stair_steps = Interval{3.0, 5.0};
    return e;
  }
  return std::nullopt;
}

std::span<const std::string_view> course_names() { return kNames; }

}  // namespace poet
