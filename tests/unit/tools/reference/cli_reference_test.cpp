// Tests tools/reference/cli_reference.cpp and the committed page it writes: an option's type, default (captured or
// stated), whether it is required and its meaning make its row; a subcommand has its section; an option whose
// default the page cannot show is refused by name; docs/reference/cli.md has a section for every binary and names
// no path of the machine it was made on. (tests/docs/check_reference_pages.py checks the page is the generator's
// output, with a diff.)

#include "tools/reference/cli_reference.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/program/command_line.h"
#include "sample_command_line.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The sample command line, as the page reads it from a binary's --help-json.
struct Tool : testing::SampleCommandLine {
  nlohmann::json json() { return nlohmann::json::parse(command_line_json(app, "poet-test").dump()); }
};

TEST(CliReference, EachOptionIsARowWithTypeDefaultRequiredAndMeaning) {
  Tool tool;
  const Expected<std::string> page = cli_reference_markdown({tool.json()});
  ASSERT_TRUE(page) << page.error();
  EXPECT_TRUE(contains(*page, "| [poet-test](#poet-test) | A test tool \\| with a bar |")) << *page;
  EXPECT_TRUE(contains(*page, "\n## poet-test\n\nA test tool \\| with a bar\n\n`poet-test [OPTIONS] [COMMAND]`\n"));
  EXPECT_TRUE(contains(*page, "| `--policy` | TEXT | — | yes | Policy file |")) << *page;
  EXPECT_TRUE(contains(*page, "| `--threads` | INT in [1 - 64] | `4` | no | Threads |")) << *page;
  EXPECT_TRUE(contains(*page, "| `--workers` | INT | one per core | no | Workers (default: one per core) |"));
  EXPECT_TRUE(contains(*page, "| `--quiet` | flag | off | no | Say less; not with `--loud` |")) << *page;
  EXPECT_TRUE(contains(*page, "| `-h`, `--help` | flag | off | no |")) << *page;
  EXPECT_TRUE(contains(*page, "\n### poet-test pair\n\nOne pair\n\n`poet-test pair [OPTIONS] ID`\n")) << *page;
  EXPECT_TRUE(contains(*page, "| `id` | INT | — | yes | The pair's id |")) << *page;
  EXPECT_TRUE(contains(*page, "| `--since` | INT | 0 | no | The first line (0-based; default 0) |")) << *page;
  // --help once, at the top level
  EXPECT_EQ(page->find("| `-h`, `--help` |"), page->rfind("| `-h`, `--help` |"));
}

TEST(CliReference, AnOptionWithoutADefaultIsRefusedByName) {
  Tool tool;
  int seed = 0;
  tool.app.get_subcommand("pair")->add_option("--seed", seed, "Seed");
  const Expected<std::string> page = cli_reference_markdown({tool.json()});
  ASSERT_FALSE(page);
  EXPECT_TRUE(contains(page.error(), "poet-test pair: --seed")) << page.error();
}

TEST(CliReference, TheCommittedPageHasEveryBinaryAndNoPathOfAMachine) {
  std::ifstream in(fs::path(POET_SOURCE_DIR) / "docs" / "reference" / "cli.md", std::ios::binary);
  ASSERT_TRUE(in);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string page = text.str();
  for (const CliBinary& binary : cli_binaries()) {
    EXPECT_TRUE(contains(page, "\n## " + std::string(binary.name) + "\n")) << binary.name;
    EXPECT_TRUE(contains(page, "`--version`")) << binary.name;
  }
  EXPECT_FALSE(contains(page, POET_SOURCE_DIR));
  EXPECT_FALSE(contains(page, "/home/"));
  EXPECT_FALSE(contains(page, "/tmp/"));
}

}  // namespace
}  // namespace poet
