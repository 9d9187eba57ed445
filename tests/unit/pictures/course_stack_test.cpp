#include "pictures/course_stack.h"

#include <gtest/gtest.h>

#include <memory>

#include "simulation/envgen/cppn_genome.h"
#include "simulation/envgen/named_courses.h"

namespace poet {
namespace {

size_t count(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t pos = 0; (pos = text.find(needle, pos)) != std::string::npos; ++pos) ++n;
  return n;
}

Terrain cppn_course(double weight) {
  EnvDef def;
  def.encoding.cppn = std::make_shared<const CppnGenome>(cppn_seed_genome(weight, 0.0));
  def.encoding.name = cppn_name(*def.encoding.cppn);
  return Terrain::generate(def);
}

TEST(CourseStack, OneBandPerCourseWithItsLabel) {
  const std::vector<LabelledCourse> courses = {{Terrain::generate({*named_course("flat"), 1}), "pair 0 flat"},
                                               {cppn_course(0.5), "pair 1 slope"},
                                               {cppn_course(2.0), "pair 2 steeper"}};
  const Expected<std::string> svg = render_course_stack(PictureFormat::kSvg, courses, 800);
  ASSERT_TRUE(svg) << svg.error();
  EXPECT_EQ(count(*svg, "fill:rgb(40%,60%,30%)"), 3u);  // each band's ground, filled
  // taller reliefs make taller bands: the stack grows with the highest relief
  const Expected<std::string> flat =
      render_course_stack(PictureFormat::kSvg, {courses[0], courses[0], courses[0]}, 800);
  ASSERT_TRUE(flat);
  const auto height_of = [](const std::string& s) { return std::stod(s.substr(s.find("height=\"") + 8)); };
  EXPECT_GT(height_of(*svg), height_of(*flat));
  const Expected<std::string> png = render_course_stack(PictureFormat::kPng, courses);
  ASSERT_TRUE(png);
  EXPECT_EQ(png->compare(0, 8, "\x89PNG\r\n\x1a\n"), 0);
}

TEST(CourseStack, Errors) {
  EXPECT_FALSE(render_course_stack(PictureFormat::kPng, {}));
  const LabelledCourse flat{Terrain::generate({*named_course("flat"), 1}), "flat"};
  EXPECT_FALSE(render_course_stack(PictureFormat::kPng, std::vector<LabelledCourse>(kMaxStackedCourses + 1, flat)));
  EXPECT_FALSE(render_course_stack(PictureFormat::kPng, {flat}, 50));
}

}  // namespace
}  // namespace poet
