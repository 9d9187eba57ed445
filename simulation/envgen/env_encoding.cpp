#include "simulation/envgen/env_encoding.h"

#include <charconv>
#include <cmath>
#include <string_view>

#include "simulation/envgen/cppn_course.h"

namespace poet {

bool EnvEncoding::same_genes(const EnvEncoding& o) const {
  return roughness == o.roughness && pit_gap == o.pit_gap && stump_width == o.stump_width &&
         stump_height == o.stump_height && stump_float == o.stump_float && stair_height == o.stair_height &&
         stair_width == o.stair_width && stair_steps == o.stair_steps &&
         (cppn == o.cppn || (cppn && o.cppn && *cppn == *o.cppn));
}

namespace {

std::optional<std::string> check_interval(std::string_view field, const std::optional<Interval>& iv, bool integer) {
  if (!iv) return std::nullopt;
  const std::string f(field);
  if (!std::isfinite(iv->lo) || !std::isfinite(iv->hi)) return f + ": bounds must be finite numbers";
  if (iv->lo < 0 || iv->hi < 0) return f + ": bounds must be >= 0";
  if (iv->lo > iv->hi) return f + ": inverted interval (lo > hi)";
  if (iv->hi > kMaxIntervalValue) return f + ": upper bound exceeds " + std::to_string(int(kMaxIntervalValue));
  if (integer) {
    if (iv->lo != std::floor(iv->lo) || iv->hi != std::floor(iv->hi)) return f + ": bounds must be whole numbers";
    if (iv->lo >= iv->hi) return f + ": integer interval [lo, hi) must hold a value (lo < hi)";
  }
  return std::nullopt;
}

std::optional<std::string> check_type(
    std::string_view type, std::initializer_list<std::pair<std::string_view, const std::optional<Interval>*>> genes) {
  int present = 0;
  for (const auto& g : genes) present += g.second->has_value() ? 1 : 0;
  if (present == 0 || present == static_cast<int>(genes.size())) return std::nullopt;
  for (const auto& g : genes)
    if (!g.second->has_value())
      return std::string(g.first) + ": missing while other " + std::string(type) +
             " intervals are given (a type is either complete or absent)";
  return std::nullopt;
}

// Python's str() of a float: shortest round-trip digits, always with a decimal point.
std::string python_float(double v) {
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, end);
  if (s.find_first_of(".eE") == std::string::npos && s != "inf" && s != "nan") s += ".0";
  return s;
}

}  // namespace

std::optional<std::string> validate(const EnvEncoding& e) {
  if (!std::isfinite(e.roughness)) return "ground_roughness: must be a finite number";
  if (e.roughness < 0) return "ground_roughness: must be >= 0";
  if (e.roughness > kMaxRoughness) return "ground_roughness: exceeds " + std::to_string(int(kMaxRoughness));
  const std::pair<std::string_view, std::pair<const std::optional<Interval>*, bool>> fields[] = {
      {"pit_gap", {&e.pit_gap, false}},           {"stump_width", {&e.stump_width, true}},
      {"stump_height", {&e.stump_height, false}}, {"stump_float", {&e.stump_float, true}},
      {"stair_height", {&e.stair_height, false}}, {"stair_width", {&e.stair_width, true}},
      {"stair_steps", {&e.stair_steps, true}},
  };
  for (const auto& [name, field] : fields)
    if (auto err = check_interval(name, *field.first, field.second)) return err;
  if (auto err = check_type(
          "stump",
          {{"stump_width", &e.stump_width}, {"stump_height", &e.stump_height}, {"stump_float", &e.stump_float}}))
    return err;
  if (auto err = check_type(
          "stair",
          {{"stair_height", &e.stair_height}, {"stair_width", &e.stair_width}, {"stair_steps", &e.stair_steps}}))
    return err;
  if (e.stump_width && e.stump_width->lo < 1) return "stump_width: a stump is at least 1 terrain step wide";
  if (e.stair_width && e.stair_width->lo < 1) return "stair_width: a stair is at least 1 terrain step wide";
  if (e.stair_steps && e.stair_steps->lo < 1) return "stair_steps: a staircase has at least 1 step";
  if (e.is_cppn()) {
    if (e.roughness != 0 || e.pit_gap || e.stump_width || e.stair_height)
      return "cppn: a CPPN course has ground_roughness 0 and no obstacle intervals";
    return validate_cppn_course(*e.cppn);
  }
  return std::nullopt;
}

std::string reference_name(const EnvEncoding& e) {
  if (e.is_cppn()) return cppn_name(*e.cppn);
  std::string name = "r" + python_float(e.roughness);
  if (e.pit_gap) name += ".p" + python_float(e.pit_gap->lo) + "_" + python_float(e.pit_gap->hi);
  if (e.has_stumps())
    name += ".b" + python_float(e.stump_width->lo) + "_" + python_float(e.stump_height->lo) + "_" +
            python_float(e.stump_height->hi);
  if (e.has_stairs()) name += ".s" + python_float(e.stair_steps->lo) + "_" + python_float(e.stair_height->hi);
  return name;
}

}  // namespace poet
