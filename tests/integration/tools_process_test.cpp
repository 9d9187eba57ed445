// Tests the command-line tools as real processes: every bad command line exits 2, --fingerprint prints the same
// text in every tool (and in this test binary, built with the same flags), --version the binary's name and the
// project's version, --help-json the command line as JSON, poet-rollout names the policy it runs,
// poet-curves summarises and draws learning curves and names a bad field.

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "child_process.h"
#include "common/program/build_fingerprint.h"
#include "common/program/command_line.h"
#include "scratch_dir.h"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using poet::testing::contains;
using poet::testing::read_file;

struct Tool {
  const char* name;
  const char* path;
};

// Every binary of the project, poet-coordinator and poet-worker included: the same rules for all.
const Tool kTools[] = {
    {"poet-coordinator", POET_COORDINATOR_BIN}, {"poet-rollout", POET_ROLLOUT_BIN},    {"poet-eval", POET_EVAL_BIN},
    {"poet-fidelity", POET_FIDELITY_BIN},       {"poet-lineage", POET_LINEAGE_BIN},    {"poet-report", POET_REPORT_BIN},
    {"poet-curves", POET_CURVES_BIN},           {"poet-worker", POET_WORKER_BIN},      {"poetctl", POETCTL_BIN},
    {"poet-controls", POET_CONTROLS_BIN},       {"poet-reference", POET_REFERENCE_BIN}};
// The build tool that writes schema_defaults.h, which the simulation waits for: the same command line without
// --fingerprint (which needs the simulation).
const Tool kBuildTool = {"poet-schema-defaults", POET_SCHEMA_DEFAULTS_BIN};

using Outcome = poet::testing::ChildOutcome;

// A fresh working directory per test, where the tools run and their output goes; any child still running is
// killed and the directory removed, even when the test failed.
class ToolsProcessTest : public ::testing::Test {
 protected:
  // Runs `path args...` in root_, stdout and stderr to root_/name.out and .err, for at most a minute.
  Outcome run(const char* path, const std::vector<std::string>& args, const std::string& name) {
    std::vector<std::string> all = {path};
    all.insert(all.end(), args.begin(), args.end());
    return children_.run(std::move(all), root_ / name, 60s, {.directory = root_});
  }

  // the children go first, the directory after them
  poet::testing::ScratchDir scratch_{"poet_tools_process_test"};
  fs::path root_ = scratch_.path();
  poet::testing::Children children_;
};

TEST_F(ToolsProcessTest, UnknownFlagExitsTwo) {
  for (const Tool& tool : kTools) {
    const Outcome o = run(tool.path, {"--no-such-flag"}, tool.name);
    EXPECT_EQ(o.code, 2) << tool.name << "\n" << o.err;
    EXPECT_FALSE(o.err.empty()) << tool.name;
  }
}

// The tools and the build tool: every binary that parses its command line through common/program.
std::vector<Tool> every_binary() {
  std::vector<Tool> tools(std::begin(kTools), std::end(kTools));
  tools.push_back(kBuildTool);
  return tools;
}

TEST_F(ToolsProcessTest, VersionPrintsTheBinarysNameAndTheProjectsVersion) {
  for (const Tool& tool : every_binary()) {
    const Outcome o = run(tool.path, {"--version"}, tool.name);
    EXPECT_EQ(o.code, 0) << tool.name << "\n" << o.err;
    EXPECT_EQ(o.out, std::string(tool.name) + " " + poet::project_version() + "\n") << tool.name;
    EXPECT_EQ(o.err, "") << tool.name;
  }
}

// What poet-reference cli reads: every binary's command line as JSON, with its name, even where options are required.
TEST_F(ToolsProcessTest, HelpJsonPrintsTheCommandLine) {
  for (const Tool& tool : every_binary()) {
    const Outcome o = run(tool.path, {"--help-json"}, tool.name);
    ASSERT_EQ(o.code, 0) << tool.name << "\n" << o.err;
    const nlohmann::json json = nlohmann::json::parse(o.out, nullptr, /*allow_exceptions=*/false);
    ASSERT_TRUE(json.is_object()) << tool.name << "\n" << o.out;
    EXPECT_EQ(json["name"], tool.name);
    EXPECT_FALSE(json["description"].get<std::string>().empty()) << tool.name;
    EXPECT_FALSE(json["options"].empty()) << tool.name;
  }
}

TEST_F(ToolsProcessTest, BadValueExitsTwo) {
  const std::vector<std::pair<const char*, std::vector<std::string>>> cases = {
      {POET_ROLLOUT_BIN, {"--lidar", "sideways"}},
      {POET_ROLLOUT_BIN, {"--push-scale", "-1"}},
      {POET_ROLLOUT_BIN, {"--max-steps", "0"}},
      {POET_EVAL_BIN, {"--policy", "none.json", "--lidar", "sideways"}},
      {POET_EVAL_BIN, {"--policy", "none.json", "--push-scale", "-1"}},
      {POET_FIDELITY_BIN, {"--threads", "0"}},
      {POET_LINEAGE_BIN, {"--run-dir", "none", "--pair", "seventeen"}},
      {POET_CURVES_BIN, {"a=none.csv", "--solved-score", "lots"}},
      {POET_COORDINATOR_BIN, {"--run-dir", "none", "--threads", "0"}},
      {POET_COORDINATOR_BIN, {"--run-dir", "none", "--log-level", "loud"}},
  };
  int n = 0;
  for (const auto& [path, args] : cases) {
    const Outcome o = run(path, args, "case" + std::to_string(n++));
    EXPECT_EQ(o.code, 2) << path << " " << args.back() << "\n" << o.err;
    EXPECT_TRUE(contains(o.err, args.back())) << path << "\n" << o.err;  // CLI11 names the bad value
  }
}

// Reference traces that lack what the table reads, or are no file at all, are an error naming the file (exit 1),
// never a crash.
TEST_F(ToolsProcessTest, FidelityNamesTheTraceFileItCannotRead) {
  const fs::path traces = root_ / "ref" / "walker-traces";
  fs::create_directories(traces);
  std::ofstream(traces / "T1_zero_action.json")
      << R"({"setup":{"bodies":[],"joints":[]},"reset":{"obs":[]},"summary":{"n_steps":1,"total_return":1}})";
  Outcome o = run(POET_FIDELITY_BIN, {"--reference", (root_ / "ref").string()}, "empty-trace");
  EXPECT_EQ(o.code, 1) << o.err;
  EXPECT_TRUE(contains(o.err, "T1_zero_action.json: ")) << o.err;
  EXPECT_TRUE(contains(o.err, "out of range")) << o.err;

  fs::remove(traces / "T1_zero_action.json");
  fs::create_directory(traces / "T1_zero_action.json");
  o = run(POET_FIDELITY_BIN, {"--reference", (root_ / "ref").string()}, "directory-trace");
  EXPECT_EQ(o.code, 1) << o.err;
  EXPECT_TRUE(contains(o.err, "T1_zero_action.json: not a file")) << o.err;
}

// A table that cannot all be written (standard output on a full device) is a failure, not a whole table.
TEST_F(ToolsProcessTest, AnOutputThatDoesNotAllGetThereExitsOne) {
  fs::create_symlink("/dev/full", root_ / "full.out");  // the child's stdout file
  const std::string walker = std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json";
  const pid_t pid =
      children_.start({POET_EVAL_BIN, "--policy", walker, "--course", "flat", "--seeds", "0:1", "--max-steps", "10"},
                      root_ / "full", {.directory = root_});
  ASSERT_GT(pid, 0);
  EXPECT_EQ(children_.wait(pid, 60s), 1);
  const std::string err = read_file(root_ / "full.err");
  EXPECT_TRUE(contains(err, "poet-eval: cannot write standard output: No space left on device")) << err;
}

// poet-eval --suite: the table has a line per group of the suite, the JSON every episode; what does not go with a
// suite, or names no suite, exits 2 saying so.
TEST_F(ToolsProcessTest, EvalRunsAPolicyOnATestSuite) {
  const std::string walker = std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json";
  const Outcome o = run(
      POET_EVAL_BIN,
      {"--policy", walker, "--suite", "poet-suite-v1", "--max-steps", "40", "--threads", "2", "--json", "suite.json"},
      "suite");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "suite poet-suite-v1: 500 episodes")) << o.out;
  for (const char* group :
       {"\neasy ", "\nchallenging ", "\nvery challenging ", "\nextremely challenging ", "\nhardcore-like "})
    EXPECT_TRUE(contains(o.out, group)) << group << "\n" << o.out;
  const nlohmann::json j = nlohmann::json::parse(read_file(root_ / "suite.json"));
  EXPECT_EQ(j["suite"], "poet-suite-v1");
  EXPECT_EQ(j["max_steps"], 40);
  EXPECT_EQ(j["episodes"], 500);
  ASSERT_EQ(j["groups"].size(), 5u);
  size_t episodes = 0;
  for (const auto& group : j["groups"])
    for (const auto& course : group["courses"]) {
      EXPECT_TRUE(course["config"].contains("ground_roughness"));
      for (const auto& e : course["episodes"]) {
        EXPECT_LE(e["steps"].get<int>(), 40);
        ++episodes;
      }
    }
  EXPECT_EQ(episodes, 500u);

  const std::vector<std::pair<std::vector<std::string>, std::string>> refused = {
      {{"--policy", walker, "--suite", "poet-suite-v0"}, "unknown suite 'poet-suite-v0'"},
      {{"--policy", walker, "--suite", "poet-suite-v1", "--course", "flat"}, "excludes"},
      {{"--policy", walker, "--suite", "poet-suite-v1", "--seeds", "0:3"}, "excludes"},
      {{"--run-dir", "somewhere"}, "requires --suite"},
      {{"--run-dir", "somewhere", "--suite", "poet-suite-v1", "--policy", walker}, "excludes"},
      {{"--run-dir", "somewhere", "--suite", "poet-suite-v1", "--push-scale", "5"}, "the run's own walker"},
      {{"--run-dir", "somewhere", "--suite", "poet-suite-v1"}, "somewhere"},
      {{"--suite", "poet-suite-v1"}, "--policy (or --run-dir with --suite) is required"},
  };
  int n = 0;
  for (const auto& [args, message] : refused) {
    const Outcome bad = run(POET_EVAL_BIN, args, "refused" + std::to_string(n++));
    EXPECT_EQ(bad.code, 2) << args.back() << "\n" << bad.err;
    EXPECT_TRUE(contains(bad.err, message)) << message << "\n" << bad.err;
  }
}

TEST_F(ToolsProcessTest, FingerprintIsTheSameInEveryTool) {
  const std::string expected = poet::build_fingerprint();
  ASSERT_TRUE(contains(expected, "digest:"));
  for (const Tool& tool : kTools) {
    const Outcome o = run(tool.path, {"--fingerprint"}, tool.name);
    EXPECT_EQ(o.code, 0) << tool.name << "\n" << o.err;
    EXPECT_EQ(o.out, expected) << tool.name;
    EXPECT_EQ(o.err, "") << tool.name;
  }
}

TEST_F(ToolsProcessTest, RolloutWithoutPolicySaysItRunsRandomTheta) {
  const Outcome o = run(POET_ROLLOUT_BIN, {"--max-steps", "50", "--picture", ""}, "rollout");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "policy: random θ")) << o.out;
  EXPECT_TRUE(contains(o.out, "no --policy given")) << o.out;
  EXPECT_TRUE(contains(o.out, "return ")) << o.out;
  // with --picture '' nothing is written: the directory holds only the captured output
  for (const auto& entry : fs::directory_iterator(root_)) {
    const std::string file = entry.path().filename().string();
    EXPECT_TRUE(file == "rollout.out" || file == "rollout.err") << file;
  }
}

// --gif writes the walker crossing its course as a looping GIF; a path that cannot be written is an error.
TEST_F(ToolsProcessTest, RolloutDrawsTheWalkAsAGif) {
  const fs::path gif = root_ / "walk.gif";
  const Outcome o = run(POET_ROLLOUT_BIN, {"--max-steps", "60", "--picture", "", "--gif", gif.string()}, "gif");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "gif: " + gif.string())) << o.out;
  std::ifstream in(gif, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.compare(0, 6, "GIF89a"), 0);
  EXPECT_TRUE(contains(bytes, "NETSCAPE2.0"));  // looping

  const Outcome bad =
      run(POET_ROLLOUT_BIN,
          {"--max-steps", "10", "--picture", "", "--gif", (root_ / "no-such-dir" / "walk.gif").string()}, "gif-bad");
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(contains(bad.err, "no-such-dir")) << bad.err;
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

TEST_F(ToolsProcessTest, CurvesSayWhenEachSolvedAndDrawThem) {
  write_text(root_ / "small.csv",
             "es_step,score,finished,env_steps,rollouts,wall_s\n"
             "1,-30.5,false,100000,64,2.0\n2,120.0,false,250000,128,4.5\n3,231.5,true,400000,192,7.0\n"
             "4,260.0,true,520000,256,9.5\n");
  // columns by name, in another order, and a step the curve script saw no time for
  write_text(root_ / "large.csv",
             "wall_s,es_step,score,finished,rollouts,env_steps\n3.0,1,-20.0,false,512,900000\n,2,229.9,true,1024,"
             "1800000\n9.0,3,240.0,false,1536,2700000\n");
  const Outcome o = run(POET_CURVES_BIN, {"64=small.csv", "512=large.csv", "--plot", "curves.png"}, "curves");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "solved at ES step 3: score 231.5, 0.4 M environment steps, 192 rollouts, 7 s")) << o.out;
  // 229.9 is below the solved score and 240.0 did not finish
  EXPECT_TRUE(contains(o.out, "not solved by ES step 3: score 240.0, 2.7 M environment steps, 1536 rollouts, 9 s"))
      << o.out;
  EXPECT_EQ(read_file(root_ / "curves.png").substr(0, 8), "\x89PNG\r\n\x1a\n");

  const Outcome lower = run(POET_CURVES_BIN, {"512=large.csv", "--solved-score", "225"}, "lower");
  ASSERT_EQ(lower.code, 0) << lower.err;
  EXPECT_TRUE(contains(lower.out, "solved at ES step 2: score 229.9")) << lower.out;
}

TEST_F(ToolsProcessTest, CurvesNameTheBadField) {
  const std::string header = "es_step,score,finished,env_steps,rollouts,wall_s\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"es_step,score,finished\n1,2,true\n", "bad0.csv:1: no column env_steps"},
      {header + "1,-3,false,10,1,0.5\n2,minus,false,20,2,1\n", "bad1.csv:3: score: not a number: \"minus\""},
      {header + "1,-3,maybe,10,1,0.5\n", "bad2.csv:2: finished: expected true or false, got \"maybe\""},
      {header + "2,-3,false,10,1,0.5\n2,-3,false,20,2,1\n", "bad3.csv:3: es_step 2 after 2: steps must increase"},
      {header + "1,-3,false,10\n", "bad4.csv:2: 4 fields, the header has 6"},
      {header, "bad5.csv: no steps after the header"},
      {"", "bad6.csv: empty"},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    const std::string file = "bad" + std::to_string(i) + ".csv";
    write_text(root_ / file, cases[i].first);
    const Outcome o = run(POET_CURVES_BIN, {"a=" + file, "--plot", "never.png"}, "bad" + std::to_string(i));
    EXPECT_EQ(o.code, 2) << file << "\n" << o.err;
    EXPECT_TRUE(contains(o.err, cases[i].second)) << o.err;
    EXPECT_FALSE(fs::exists(root_ / "never.png")) << file;
  }
  const Outcome missing = run(POET_CURVES_BIN, {"a=absent.csv"}, "missing");
  EXPECT_EQ(missing.code, 2);
  EXPECT_TRUE(contains(missing.err, "poet-curves: absent.csv: does not exist")) << missing.err;
  // a directory where a file should be: an error naming it, not an uncaught exception
  fs::create_directories(root_ / "d.csv");
  const Outcome directory = run(POET_CURVES_BIN, {"a=d.csv"}, "directory");
  EXPECT_EQ(directory.code, 2) << directory.err;
  EXPECT_TRUE(contains(directory.err, "poet-curves: d.csv: is a directory")) << directory.err;
  EXPECT_FALSE(contains(directory.err, "terminate")) << directory.err;
  const Outcome unlabelled = run(POET_CURVES_BIN, {"small.csv"}, "unlabelled");
  EXPECT_EQ(unlabelled.code, 2);
  EXPECT_TRUE(contains(unlabelled.err, "poet-curves: \"small.csv\" is not LABEL=CURVE.csv")) << unlabelled.err;
}

TEST_F(ToolsProcessTest, CurvesSavedByASpreadsheetAreRead) {
  // a byte-order mark and "\r\n" line ends, as spreadsheet programs save CSV on Windows
  write_text(root_ / "saved.csv",
             "\xEF\xBB\xBF"
             "es_step,score,finished,env_steps,rollouts,wall_s\r\n1,-30.5,false,100000,64,2.0\r\n"
             "2,231.5,true,250000,128,4.5\r\n");
  const Outcome o = run(POET_CURVES_BIN, {"saved=saved.csv"}, "saved");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.out, "solved at ES step 2: score 231.5")) << o.out;
}

}  // namespace
