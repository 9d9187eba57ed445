#include "simulation/envgen/cppn_course.h"

#include <cmath>
#include <numbers>

#include "simulation/walker/walker_constants.h"

namespace poet {

using walker::kTerrainLength;
using walker::kTerrainStartpad;
using walker::kTerrainStep;

double cppn_course_x(int point) {
  const double mid = kTerrainLength * kTerrainStep / 2.0;
  return (point * kTerrainStep - mid) * std::numbers::pi / mid;
}

std::vector<double> cppn_relief(const CppnGenome& genome) {
  std::vector<double> xs;
  for (int i = kTerrainStartpad + 1; i < kTerrainLength; ++i) xs.push_back(cppn_course_x(i));
  const std::vector<double> ys = cppn_outputs(genome, xs);
  std::vector<double> relief(kTerrainStartpad + 1, 0.0);
  for (double y : ys) relief.push_back(y - ys.front());
  return relief;
}

std::optional<std::string> validate_cppn_course(const CppnGenome& genome) {
  if (auto err = validate(genome)) return err;
  for (double h : cppn_relief(genome))
    if (!std::isfinite(h) || std::abs(h) > kMaxCppnRelief)
      return std::string("cppn: the course's ground leaves ±100 m of the start pad (or overflows)");
  return std::nullopt;
}

}  // namespace poet
