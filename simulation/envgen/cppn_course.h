#pragma once
// A CPPN genome drawn as a course's ground, as the authors' walker draws it: the start pad is flat, and from the
// point after it the height is the network's output at x′ = (x − mid)·π/mid (x′ in [−π, π) over the course, mid its
// half length) minus the output at that first point, so the ground is continuous where the pad ends.

#include <optional>
#include <string>
#include <vector>

#include "simulation/envgen/cppn_genome.h"

namespace poet {

// The highest or lowest a valid CPPN course's ground may go from the start pad, in metres: mutation keeps the rise
// within 16 m, and beyond this a course stops being a walker course.
inline constexpr double kMaxCppnRelief = 100.0;

// x′ of course point i.
double cppn_course_x(int point);

// The ground height of every course point relative to the start pad (kTerrainLength values; 0 on the pad), for a
// valid genome. May be non-finite when the network overflows.
std::vector<double> cppn_relief(const CppnGenome& genome);

// validate(genome), then the relief: finite and within ±kMaxCppnRelief. Returns a message naming the field.
std::optional<std::string> validate_cppn_course(const CppnGenome& genome);

}  // namespace poet
