// Tests report/learning_curves.cpp's reading: CSV saved with "\r\n" line ends and a UTF-8 byte-order mark reads as
// the same curve, and a path that is not a regular file of bounded size is an error naming it, never an exception.

#include "report/learning_curves.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

constexpr char kCurve[] =
    "es_step,score,finished,env_steps,rollouts,wall_s\n1,-30.5,false,100000,64,2.0\n2,231.5,true,250000,128,4.5\n";

std::string windows_lines(std::string text) {
  for (size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 2)) text.insert(at, "\r");
  return text;
}

TEST(LearningCurves, CrlfLinesAndAByteOrderMarkReadAsTheSameCurve) {
  const Expected<LearningCurve> plain = parse_learning_curve(kCurve, "plain.csv");
  ASSERT_TRUE(plain) << plain.error();
  for (const std::string& text :
       {windows_lines(kCurve), "\xEF\xBB\xBF" + std::string(kCurve), "\xEF\xBB\xBF" + windows_lines(kCurve)}) {
    const Expected<LearningCurve> curve = parse_learning_curve(text, "saved.csv");
    ASSERT_TRUE(curve) << curve.error();
    ASSERT_EQ(curve->points.size(), plain->points.size());
    EXPECT_EQ(curve->points.back().wall_s, 4.5);  // the last column, where a '\r' would sit
    EXPECT_TRUE(curve->points.back().finished);
  }
  // a mark anywhere else is still what it is
  const Expected<LearningCurve> inside = parse_learning_curve("es_step,\xEF\xBB\xBFscore\n", "inside.csv");
  ASSERT_FALSE(inside);
  EXPECT_NE(inside.error().find("no column score"), std::string::npos) << inside.error();
}

TEST(LearningCurves, AFileThatIsNotACurveFileIsAnErrorNamingIt) {
  const poet::testing::ScratchDir scratch("poet_learning_curves_test");
  const fs::path dir = scratch.path() / "d.csv";
  fs::create_directories(dir);
  for (const auto& [path, why] :
       {std::pair{dir, "is a directory"}, std::pair{scratch.path() / "absent.csv", "does not exist"}}) {
    const Expected<LearningCurve> curve = read_learning_curve(path.string());
    ASSERT_FALSE(curve) << path;
    EXPECT_NE(curve.error().find(path.string() + ": " + why), std::string::npos) << curve.error();
  }
  const fs::path huge = scratch.path() / "huge.csv";
  std::ofstream(huge) << kCurve;
  fs::resize_file(huge, std::uintmax_t{65} << 20);  // sparse: refused by its size, never read
  const Expected<LearningCurve> too_large = read_learning_curve(huge.string());
  ASSERT_FALSE(too_large);
  EXPECT_NE(too_large.error().find("huge.csv: is larger than"), std::string::npos) << too_large.error();
  const fs::path good = scratch.path() / "good.csv";
  std::ofstream(good) << kCurve;
  EXPECT_TRUE(read_learning_curve(good.string()));
}

}  // namespace
}  // namespace poet
