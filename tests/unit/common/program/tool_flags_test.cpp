#include "common/program/tool_flags.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "command_args.h"
#include "common/program/build_fingerprint.h"

namespace poet {
namespace {

// A tool's command line: the walker flags, --fingerprint and one required option.
struct Tool {
  CLI::App app{"test tool"};
  WalkerFlags walker;
  std::string policy;

  Tool() {
    app.add_option("--policy", policy, "Policy file")->required();
    add_walker_flags(app, walker);
    add_fingerprint_flag(app);
  }

  std::optional<int> parse(std::vector<std::string> args) {
    testing::CommandArgs a("poet-test", std::move(args));
    return parse_command_line(app, a.argc(), a.argv());
  }
};

TEST(ToolFlags, GoodCommandLineContinues) {
  Tool tool;
  EXPECT_EQ(tool.parse({"--policy", "p.json"}), std::nullopt);
  EXPECT_EQ(tool.policy, "p.json");
}

TEST(ToolFlags, BadCommandLinesExitTwoWithCli11sMessage) {
  const std::vector<std::vector<std::string>> bad = {
      {"--policy", "p.json", "--no-such-flag"},       // unknown flag (CLI11: 109)
      {"--policy", "p.json", "--push-scale", "-1"},   // out of range (CLI11: 105)
      {"--policy", "p.json", "--lidar", "sideways"},  // not a member
      {"--policy", "p.json", "--max-steps", "0"},     // out of range
      {"--policy", "p.json", "--max-steps", "many"},  // not a number
      {"--lidar", "first"},                           // missing required option (CLI11: 106)
  };
  for (const auto& args : bad) {
    Tool tool;
    ::testing::internal::CaptureStderr();
    const std::optional<int> code = tool.parse(args);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(code, kExitUsage) << args.back();
    EXPECT_FALSE(err.empty()) << args.back();
  }
  EXPECT_EQ(kExitUsage, 2);
}

TEST(ToolFlags, HelpExitsZero) {
  Tool tool;
  ::testing::internal::CaptureStdout();
  const std::optional<int> code = tool.parse({"--help"});
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(code, 0);
  EXPECT_NE(out.find("--push-scale"), std::string::npos) << out;
  EXPECT_NE(out.find("--fingerprint"), std::string::npos) << out;
}

TEST(ToolFlags, FingerprintPrintsItAndExitsZeroWithoutRequiredOptions) {
  Tool tool;
  ::testing::internal::CaptureStdout();
  const std::optional<int> code = tool.parse({"--fingerprint"});
  const std::string out = ::testing::internal::GetCapturedStdout();
  EXPECT_EQ(code, 0);
  EXPECT_EQ(out, build_fingerprint());
}

TEST(ToolFlags, WalkerFlagsMapToWalkerOptions) {
  Tool defaults;
  ASSERT_EQ(defaults.parse({"--policy", "p.json"}), std::nullopt);
  EXPECT_EQ(defaults.walker.options().push_scale, walker::kDefaultPushScale);
  EXPECT_EQ(defaults.walker.options().lidar, LidarRule::kNearest);
  EXPECT_EQ(defaults.walker.max_steps, walker::kDefaultTimeLimit);

  Tool set;
  ASSERT_EQ(set.parse({"--policy", "p.json", "--push-scale", "0", "--lidar", "first", "--max-steps", "50"}),
            std::nullopt);
  EXPECT_EQ(set.walker.options().push_scale, 0.0);
  EXPECT_EQ(set.walker.options().lidar, LidarRule::kFirst);
  EXPECT_EQ(set.walker.max_steps, 50);
}

}  // namespace
}  // namespace poet
