#pragma once
// Courses one above another, each a band with its label: the environments along a lineage, ancestor first, so a
// reader sees how the ground changed from one generation to the next (Enhanced POET's CPPN terrains, or obstacle
// courses).

#include <string>
#include <vector>

#include "common/plumbing/expected.h"
#include "pictures/canvas.h"
#include "simulation/walker/terrain.h"

namespace poet {

struct LabelledCourse {
  Terrain terrain;
  std::string label;
};

// Every band is drawn at one scale, the same for both axes and every band, so heights compare: the whole course
// across `width` units unless the highest relief would make a band taller than 600. An error for no course, more
// than kMaxStackedCourses or a width outside [200, 4000].
inline constexpr size_t kMaxStackedCourses = 64;
Expected<std::string> render_course_stack(PictureFormat format, const std::vector<LabelledCourse>& courses,
                                          double width = 1200);

}  // namespace poet
