#include "common/program/command_line.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "command_args.h"
#include "common/program/build_fingerprint.h"
#include "sample_command_line.h"

namespace poet {
namespace {

// The sample command line, parsed as a binary's main() parses its own.
struct Tool : testing::SampleCommandLine {
  std::optional<int> parse(std::vector<std::string> args, std::string program = "/opt/poet/bin/poet-test") {
    testing::CommandArgs a(std::move(program), std::move(args));
    return parse_command_line(app, a.argc(), a.argv());
  }
};

// What a parse printed on standard output, and its result.
struct Printed {
  std::optional<int> code;
  std::string out;
};

Printed parse_printing(Tool& tool, std::vector<std::string> args) {
  ::testing::internal::CaptureStdout();
  const std::optional<int> code = tool.parse(std::move(args));
  return {code, ::testing::internal::GetCapturedStdout()};
}

TEST(CommandLine, VersionPrintsTheBinarysNameAndTheProjectsVersionWithoutRequiredOptions) {
  Tool tool;
  const Printed printed = parse_printing(tool, {"--version"});
  EXPECT_EQ(printed.code, 0);
  EXPECT_EQ(printed.out, std::string("poet-test ") + project_version() + "\n");
  // the version the fingerprint names
  EXPECT_NE(build_fingerprint().find(std::string("poet: ") + project_version() + "\n"), std::string::npos);
  EXPECT_FALSE(std::string(project_version()).empty());
}

TEST(CommandLine, HelpListsVersionButNotHelpJson) {
  Tool tool;
  const Printed printed = parse_printing(tool, {"--help"});
  EXPECT_EQ(printed.code, 0);
  EXPECT_NE(printed.out.find("--version"), std::string::npos) << printed.out;
  EXPECT_EQ(printed.out.find("--help-json"), std::string::npos) << printed.out;
  EXPECT_EQ(printed.out.find("--hidden"), std::string::npos) << printed.out;
}

TEST(CommandLine, ParsingTwiceAddsTheStandardFlagsOnce) {
  Tool tool;
  EXPECT_EQ(tool.parse({"--policy", "p.json"}), std::nullopt);
  EXPECT_EQ(tool.parse({"--policy", "q.json"}), std::nullopt);
  EXPECT_EQ(tool.policy, "q.json");
}

TEST(CommandLine, HelpJsonDescribesEveryOptionAndSubcommandButTheHiddenOnes) {
  Tool tool;
  const Printed printed = parse_printing(tool, {"--help-json"});
  ASSERT_EQ(printed.code, 0);  // without the required --policy
  const nlohmann::json json = nlohmann::json::parse(printed.out);
  EXPECT_EQ(json["name"], "poet-test");
  EXPECT_EQ(json["description"], "A test tool | with a bar");
  std::map<std::string, nlohmann::json> options;
  for (const nlohmann::json& option : json["options"]) options[option["names"].back()] = option;
  EXPECT_EQ(options.count("--hidden"), 0u);
  EXPECT_EQ(options.count("--help-json"), 0u);
  ASSERT_EQ(options.count("--version"), 1u);
  ASSERT_EQ(options.count("--help"), 1u);
  EXPECT_EQ(options["--help"]["names"], nlohmann::json::array({"-h", "--help"}));

  const nlohmann::json& policy = options["--policy"];
  EXPECT_EQ(policy["type"], "TEXT");
  EXPECT_EQ(policy["required"], true);
  EXPECT_EQ(policy["flag"], false);
  EXPECT_EQ(policy["description"], "Policy file");
  const nlohmann::json& threads = options["--threads"];
  EXPECT_EQ(threads["type"], "INT");
  EXPECT_EQ(threads["check"], "INT in [1 - 64]");
  EXPECT_EQ(threads["default"], "4");
  EXPECT_EQ(threads["required"], false);
  EXPECT_EQ(options["--workers"]["default"], "");  // not captured: the description says it
  EXPECT_EQ(options["--quiet"]["flag"], true);
  EXPECT_EQ(options["--quiet"]["excludes"], nlohmann::json::array({"--loud"}));

  ASSERT_EQ(json["subcommands"].size(), 1u);
  const nlohmann::json& pair = json["subcommands"][0];
  EXPECT_EQ(pair["name"], "pair");
  EXPECT_EQ(pair["description"], "One pair");
  bool has_id = false;
  for (const nlohmann::json& option : pair["options"]) {
    if (option["names"] != nlohmann::json::array({"id"})) continue;
    has_id = true;
    EXPECT_EQ(option["positional"], true);
    EXPECT_EQ(option["required"], true);
  }
  EXPECT_TRUE(has_id) << pair.dump();
}

}  // namespace
}  // namespace poet
