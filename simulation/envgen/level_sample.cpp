#include "simulation/envgen/level_sample.h"

namespace poet {

EnvVector draw_env_vector(RandomStream& stream, Difficulty level) {
  for (;;) {
    EnvVector e{};
    for (size_t i = 0; i < e.size(); ++i) e[i] = stream.uniform(0.0, kEnvVectorMax[i]);
    if (e[1] > e[2] || e[3] > e[4]) continue;  // lo ≤ hi for the gap and the stump height
    if (difficulty(e) == level) return e;
  }
}

EnvEncoding course_of(const EnvVector& e, std::string name) {
  EnvEncoding course;
  course.name = std::move(name);
  course.roughness = e[0];
  if (e[2] > 0) course.pit_gap = Interval{e[1], e[2]};
  if (e[4] > 0) {
    course.stump_height = Interval{e[3], e[4]};
    course.stump_width = Interval{1, 2};
    course.stump_float = Interval{0, 1};
  }
  return course;
}

}  // namespace poet
