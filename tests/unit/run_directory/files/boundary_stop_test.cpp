// Tests run_directory/files/boundary_stop.cpp: a request is written, seen and removed; removing none is no error.

#include "run_directory/files/boundary_stop.h"

#include <gtest/gtest.h>

#include "common/plumbing/text_file.h"
#include "scratch_dir.h"

namespace poet {
namespace {

TEST(BoundaryStop, ARequestIsSeenUntilCleared) {
  testing::ScratchDir dir("boundary_stop_test");
  ASSERT_FALSE(boundary_stop_requested(dir.path()).value());
  ASSERT_EQ(request_boundary_stop(dir.path(), "a test"), std::nullopt);
  EXPECT_TRUE(boundary_stop_requested(dir.path()).value());
  EXPECT_NE(read_text_file(dir.path() / kBoundaryStopFile, 4096).value().find("a test"), std::string::npos);
  EXPECT_EQ(clear_boundary_stop(dir.path()), std::nullopt);
  EXPECT_FALSE(boundary_stop_requested(dir.path()).value());
  EXPECT_EQ(clear_boundary_stop(dir.path()), std::nullopt);
}

TEST(BoundaryStop, AMissingDirectoryIsAnError) {
  testing::ScratchDir dir("boundary_stop_test");
  EXPECT_TRUE(request_boundary_stop(dir.path() / "absent", "a test"));
}

}  // namespace
}  // namespace poet
