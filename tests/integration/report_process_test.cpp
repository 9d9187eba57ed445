// poet-report and `poetctl picture` as real processes on real run directories: a finished POET run started from
// the shipped walker (children admitted and solved, transfers accepted), a live run being written (pictures from
// its status socket), and damaged, incomplete and newer-format directories. Neither changes a run directory:
// every test compares its files before and after.

#include <nlohmann/json.hpp>
#include <tuple>

#include "coordinator_run_fixture.h"

namespace poet::testing {
namespace {

// Starting from the walker that solves flat, its children are solved at admission within a few iterations.
constexpr char kWalkerConfig[] = R"(mode: POET
seed: 3
iterations: 3
es { perturbations: 2 init_lr: 0.02 }
poet { mutation_interval: 1 transfer_interval: 2 repro_threshold: 200 mc_low: 50 mc_high: 340
       max_children: 4 max_admitted: 2 active_cap: 4 }
)";

// The same on CPPN terrain: the walker that solves flat meets slopes and hills.
constexpr char kCppnWalkerConfig[] = R"(mode: POET
seed: 3
iterations: 3
es { perturbations: 2 init_lr: 0.02 }
poet { mutation_interval: 1 transfer_interval: 2 repro_threshold: 200 mc_low: 25 mc_high: 340
       max_children: 4 max_admitted: 2 active_cap: 4 environments: CPPN_TERRAIN novelty: PATA_EC }
)";

// Every file under dir (relative path → content and modification time).
std::map<std::string, std::pair<std::string, fs::file_time_type>> files_of(const fs::path& dir) {
  std::map<std::string, std::pair<std::string, fs::file_time_type>> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file())
      files[fs::relative(entry.path(), dir).string()] = {read(entry.path()), entry.last_write_time()};
  return files;
}

class ReportProcessTest : public CoordinatorRunTest {
 protected:
  // Runs a tool with args to its end; its exit code, stdout in *out and stderr in *err.
  int tool(const char* binary, std::vector<std::string> args, std::string* out, std::string* err) {
    const std::string name = "tool" + std::to_string(runs_++);
    const int code = wait(spawn(binary, std::move(args), name));
    if (out) *out = read(root_ / (name + ".out"));
    if (err) *err = read(root_ / (name + ".err"));
    return code;
  }
  int report(std::vector<std::string> args, std::string* out = nullptr, std::string* err = nullptr) {
    return tool(POET_REPORT_BIN, std::move(args), out, err);
  }
  int poetctl(std::vector<std::string> args, std::string* out = nullptr, std::string* err = nullptr) {
    return tool(POETCTL_BIN, std::move(args), out, err);
  }

  fs::path walker_run(const char* config_text = kWalkerConfig, const std::string& name = "walker") {
    const fs::path config = root_ / (name + ".textproto");
    std::ofstream(config) << config_text;
    const fs::path dir = root_ / name;
    const pid_t pid = spawn(POET_COORDINATOR_BIN,
                            {"--config", config.string(), "--run-dir", dir.string(), "--start-from",
                             std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json", "--threads", "2",
                             "--quiet", "--status-address", ""},
                            name);
    EXPECT_EQ(wait(pid), 0) << read(root_ / (name + ".err"));
    return dir;
  }

  int runs_ = 0;
};

// The magic bytes of each picture format.
bool is_png(const std::string& bytes) { return bytes.size() > 100 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0; }
bool is_svg(const std::string& bytes) { return bytes.size() > 100 && contains(bytes.substr(0, 200), "<svg"); }
bool is_gif(const std::string& bytes) {
  return bytes.size() > 1000 && bytes.compare(0, 6, "GIF89a") == 0 && contains(bytes, "NETSCAPE2.0");
}

TEST_F(ReportProcessTest, ReportsTheMetricsTableJsonAndPlotsOfAFinishedRunWithoutChangingIt) {
  const fs::path run = walker_run();
  const auto before = files_of(run);
  std::string table, err;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", (root_ / "report.json").string(), "--plots",
                    (root_ / "plots").string(), "--coverage-samples", (root_ / "coverage.csv").string(),
                    "--coverage-per-level", "50"},
                   &table, &err),
            0)
      << err;
  EXPECT_TRUE(before == files_of(run)) << "the run directory changed";

  for (const char* line : {"Environments by difficulty level", "When each level was first reached",
                           "Where the time went", "Lineage of the deepest solved environment",
                           "Transfers:", "ANNECS at admission:", "ANNECS at archiving:", "Coverage (seed", "Pairs"})
    EXPECT_TRUE(contains(table, line)) << line << "\n" << table;

  const nlohmann::json j = nlohmann::json::parse(read(root_ / "report.json"));
  EXPECT_EQ(j["iterations_done"], 3);
  EXPECT_EQ(j["finished"], true);
  EXPECT_EQ(j["live"], false);
  ASSERT_EQ(j["levels"].size(), 4u);
  const nlohmann::json& easy = j["levels"][0];
  EXPECT_EQ(easy["level"], "easy");
  // the walker's children pass the MC, are admitted and solved; the pairs list agrees with the counts
  EXPECT_GE(easy["created"].get<int>(), easy["passed_mc"].get<int>());
  EXPECT_GE(easy["admitted"].get<int>(), 3);
  EXPECT_EQ(easy["admitted"].get<size_t>(), j["pairs"].size());
  EXPECT_GE(easy["solved"].get<int>(), 3);
  EXPECT_EQ(easy["iterations_to_solve"]["count"], easy["solved"]);
  // the first environment is admitted and solved at iteration 0, with the coordinator's wall time of it
  EXPECT_EQ(easy["first_admitted"]["iteration"], 0);
  EXPECT_EQ(easy["first_solved"]["iteration"], 0);
  EXPECT_GT(easy["first_solved"]["rollouts"].get<int64_t>(), 0);
  EXPECT_GT(easy["first_solved"]["env_steps"].get<int64_t>(), 0);
  EXPECT_GE(easy["first_solved"]["wall_s"].get<double>(), 0.0);
  EXPECT_TRUE(j["levels"][1]["first_created"].is_null());
  EXPECT_TRUE(j["wall_times_problem"].is_null());
  // the deepest solved lineage starts at the first environment
  ASSERT_EQ(j["goal_switching"].size(), 1u);
  EXPECT_EQ(j["goal_switching"][0]["chain"][0]["pair"], 0);
  EXPECT_EQ(j["over_time"].size(), 3u);
  EXPECT_EQ(j["over_time"][2]["admitted"][0], easy["admitted"]);
  EXPECT_GT(j["transfers"]["replacement_attempts"].get<int>(), 0);
  EXPECT_EQ(j["transfers"]["accepted"].get<size_t>(), j["transfers"]["accepted_list"].size());
  EXPECT_GE(j["annecs"]["at_admission"]["value"].get<int>(), 2);
  EXPECT_FALSE(j["annecs"]["at_admission"]["definition"].get<std::string>().empty());
  EXPECT_FALSE(j["annecs"]["at_archiving"]["definition"].get<std::string>().empty());
  // the frontier: a point per iteration, never going back
  const nlohmann::json& frontier = j["frontier"];
  ASSERT_EQ(frontier.size(), 3u);
  for (const char* measure : {"roughness", "gap_hi", "stump_hi"})
    EXPECT_LE(frontier[0]["solved"][measure].get<double>(), frontier[2]["solved"][measure].get<double>()) << measure;
  // ANNECS over time: a point per iteration ending at the values, as annecs.csv holds them
  const nlohmann::json& annecs = j["annecs"]["over_time"];
  ASSERT_EQ(annecs.size(), 3u);
  EXPECT_EQ(annecs[2]["at_admission"], j["annecs"]["at_admission"]["value"]);
  EXPECT_EQ(annecs[2]["at_archiving"], j["annecs"]["at_archiving"]["value"]);
  EXPECT_EQ(annecs[2]["at_archiving"], 1);  // the solved first pair, retired at iteration 2 past the cap of 4
  std::string lines = "iteration,annecs_at_admission,annecs_at_archiving\n";
  for (size_t t = 0; t < annecs.size(); ++t) {
    EXPECT_EQ(annecs[t]["iteration"], t);
    if (t > 0) {
      EXPECT_GE(annecs[t]["at_admission"], annecs[t - 1]["at_admission"]);
    }
    lines += std::to_string(t) + "," + annecs[t]["at_admission"].dump() + "," + annecs[t]["at_archiving"].dump() + "\n";
  }
  EXPECT_EQ(read(run / "annecs.csv"), lines);
  EXPECT_TRUE(j["coverage"]["sum"]["challenging"].is_null());  // nothing solved at challenging or above
  // where the time went: the three iterations in blocks of one, each timed, its phases within its wall time
  const nlohmann::json& phases = j["time_per_phase"];
  ASSERT_EQ(phases.size(), 3u);
  for (const nlohmann::json& block : phases) {
    EXPECT_EQ(block["timed_iterations"], 1);
    double timed = 0;
    for (const char* phase : {"reproduction_s", "es_steps_s", "evaluations_s", "transfer_s"})
      timed += block[phase].get<double>();
    EXPECT_GT(block["es_steps_s"].get<double>(), 0.0);
    EXPECT_LE(timed, block["wall_s"].get<double>() + 1e-3);
    // the run loop waited for rollouts for part of its phases; the rest was its own work
    EXPECT_EQ(block["waited_iterations"], 1);
    EXPECT_GT(block["waiting_s"].get<double>(), 0.0);
    EXPECT_LE(block["waiting_s"].get<double>(), timed + 1e-3);
    EXPECT_DOUBLE_EQ(block["waited_wall_s"].get<double>(), block["wall_s"].get<double>());
  }

  // coverage sample: a header and 50 samples per level, none with a distance
  const std::string samples = read(root_ / "coverage.csv");
  EXPECT_EQ(std::count(samples.begin(), samples.end(), '\n'), 151);
  EXPECT_TRUE(contains(samples, "very challenging,"));
  for (const char* plot :
       {"scores.png", "levels.png", "annecs.png", "frontier.png", "phases.png", "tree.png", "lineage.png"}) {
    const std::string png = read(root_ / "plots" / plot);
    ASSERT_GT(png.size(), 1000u) << plot;
    EXPECT_EQ(png.substr(1, 3), "PNG") << plot;
  }
  // the table is the same run: "--json -" prints the same JSON
  std::string json_out;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "50", "--coverage-samples",
                    (root_ / "coverage.csv").string(), "--plots", (root_ / "plots").string()},
                   &json_out),
            0);
  EXPECT_EQ(nlohmann::json::parse(json_out), j);
}

// --until-iteration and --until-env-steps report the run as it stood earlier (run_directory/reading/run_cut.h checks
// the numbers).
TEST_F(ReportProcessTest, ARunIsReportedAsItStoodAtABudget) {
  const fs::path run = threads_run();
  std::string full, err;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "5"}, &full, &err), 0) << err;
  const nlohmann::json j = nlohmann::json::parse(full);
  const int done = j["iterations_done"].get<int>();
  ASSERT_GE(done, 3);
  std::string cut;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "5", "--until-iteration", "1"},
                   &cut, &err),
            0)
      << err;
  EXPECT_EQ(nlohmann::json::parse(cut)["iterations_done"], 2);
  // a budget of the whole run's steps cuts nothing; one below iteration 0's is refused
  std::string same;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "5", "--until-env-steps",
                    std::to_string(j["env_steps"].get<int64_t>())},
                   &same, &err),
            0)
      << err;
  EXPECT_EQ(nlohmann::json::parse(same)["iterations_done"], done);
  std::string table;
  EXPECT_EQ(report({"--run-dir", run.string(), "--until-env-steps", "1"}, &table, &err), 2);
  EXPECT_TRUE(contains(err, "the run's first iteration took more")) << err;
  EXPECT_EQ(report({"--run-dir", run.string(), "--until-env-steps", "5", "--until-iteration", "1"}, &table, &err), 2);
}

// Every agent of a run on the test suite: poet-eval --run-dir and poet-report --suite give the same figures and the
// same best agents, and neither changes the run directory. A run with short episodes keeps the suite quick.
TEST_F(ReportProcessTest, TheRunsAgentsOnATestSuiteAreTheSameInPoetEvalAndPoetReport) {
  const fs::path run = threads_run();
  const auto before = files_of(run);
  std::string eval_out, report_out, err;
  ASSERT_EQ(tool(POET_EVAL_BIN,
                 {"--run-dir", run.string(), "--suite", "poet-suite-v1", "--threads", "2", "--json",
                  (root_ / "eval.json").string()},
                 &eval_out, &err),
            0)
      << err;
  ASSERT_EQ(report({"--run-dir", run.string(), "--suite", "poet-suite-v1", "--threads", "2", "--json", "-",
                    "--coverage-per-level", "5"},
                   &report_out, &err),
            0)
      << err;
  EXPECT_TRUE(before == files_of(run)) << "the run directory changed";
  const nlohmann::json eval = nlohmann::json::parse(read(root_ / "eval.json"));
  const nlohmann::json report_suite = nlohmann::json::parse(report_out)["suite"];
  ASSERT_GE(eval["candidates"].size(), 3u) << "each pair's θ, and its best θ where it differs";
  ASSERT_EQ(eval["candidates"].size(), report_suite["candidates"].size());
  for (size_t i = 0; i < eval["candidates"].size(); ++i) {
    const nlohmann::json& a = eval["candidates"][i];
    const nlohmann::json& b = report_suite["candidates"][i];
    EXPECT_EQ(a["label"], b["label"]);
    nlohmann::json summary = a["score"];
    for (auto& group : summary["groups"]) group.erase("courses");  // poet-report's JSON carries no episodes
    EXPECT_EQ(summary, b["score"]) << a["label"];
    EXPECT_EQ(a["score"]["episodes"], 500);
  }
  EXPECT_EQ(eval["best"], report_suite["best"]);
  EXPECT_EQ(eval["best_per_group"], report_suite["best_per_group"]);
  EXPECT_TRUE(contains(eval_out, "best single agent on poet-suite-v1: " + eval["best"].get<std::string>())) << eval_out;
  EXPECT_TRUE(contains(eval_out, "best on extremely challenging: ")) << eval_out;

  std::string table;
  EXPECT_EQ(report({"--run-dir", run.string(), "--suite", "poet-suite-v0"}, &table, &err), 2);
  EXPECT_TRUE(contains(err, "unknown suite 'poet-suite-v0'")) << err;
  EXPECT_EQ(report({"--run-dir", run.string(), "--suite", "poet-suite-v1", "--until-iteration", "1"}, &table, &err), 2);
  EXPECT_TRUE(contains(err, "excludes")) << err;
}

// env_step_budget ends a run after the iteration that reaches it: the coordinator says so, and the report calls the
// run finished although its iteration limit is far.
TEST_F(ReportProcessTest, ARunEndsOnItsEnvironmentStepBudget) {
  std::ofstream(config_, std::ios::trunc) << config_with("iterations: 6", "iterations: 1000 env_step_budget: 2000");
  const pid_t pid = coordinator(root_ / "B", {"--threads", "2"}, "B");
  ASSERT_EQ(wait(pid), 0) << read(root_ / "B.err");
  EXPECT_TRUE(contains(read(root_ / "B.err"), "its environment-step budget of 2000 reached")) << read(root_ / "B.err");
  std::string out, err;
  ASSERT_EQ(report({"--run-dir", (root_ / "B").string(), "--json", "-", "--coverage-per-level", "5"}, &out, &err), 0)
      << err;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_TRUE(j["finished"].get<bool>());
  EXPECT_LT(j["iterations_done"].get<int>(), 1000);
  EXPECT_GE(j["env_steps"].get<int64_t>(), 2000);
  ASSERT_EQ(report({"--run-dir", (root_ / "B").string(), "--coverage-per-level", "5"}, &out, &err), 0) << err;
  EXPECT_TRUE(contains(out, "(budget 0.0 M, reached)")) << out;
}

// The controls of a POET-solved environment (experiments/controls.sh, figure3.sh): poet-lineage writes the ES-alone and
// direct-path configs with the lineage's budget (and a seed of their own), both run to their end as written, and
// poet-controls sets them beside the lineage, in ES steps and environment steps, and draws the rose.
TEST_F(ReportProcessTest, LineageWritesRunnableControlConfigsWithTheLineagesBudget) {
  const fs::path run = walker_run();
  std::string text, err;
  ASSERT_EQ(tool(POET_LINEAGE_BIN, {"--run-dir", run.string(), "--pair", "1"}, &text, &err), 0) << err;
  const size_t at = text.find("direct-path budget: ");
  ASSERT_NE(at, std::string::npos) << text;
  const int budget = std::stoi(text.substr(at + 20));
  ASSERT_GT(budget, 0);
  const size_t steps_at = text.find("environment steps of those ES steps: ");
  ASSERT_NE(steps_at, std::string::npos) << text;
  const int64_t lineage_env_steps = std::stoll(text.substr(steps_at + 37));
  ASSERT_GT(lineage_env_steps, 0) << text;

  for (const char* flag : {"--es-alone-config", "--direct-path-config"}) {
    ASSERT_EQ(tool(POET_LINEAGE_BIN, {"--run-dir", run.string(), "--pair", "1", flag, "--seed", "9"}, &text, &err), 0)
        << err;
    const bool es_alone = std::string(flag) == "--es-alone-config";
    EXPECT_TRUE(contains(text, "seed: 9")) << text;
    EXPECT_TRUE(contains(text, es_alone ? "mode: ES_ALONE" : "mode: DIRECT_PATH")) << text;
    EXPECT_EQ(contains(text, "stop_when_solved: true"), es_alone) << "ES alone stops as the direct path does: " << text;
    EXPECT_TRUE(contains(
        text, es_alone ? "iterations: " + std::to_string(budget) : "budget_es_steps: " + std::to_string(budget)))
        << text;
    const fs::path config = root_ / (std::string(flag + 2) + ".textproto");
    std::ofstream(config) << text;
    const fs::path dir = root_ / flag;
    const std::string name = flag + 2;
    std::vector<std::string> args = {"--config",
                                     config.string(),
                                     "--run-dir",
                                     dir.string(),
                                     "--start-from",
                                     std::string(POET_SOURCE_DIR) + "/data/walkers/flat-walker.json",
                                     "--threads",
                                     "2",
                                     "--quiet",
                                     "--status-address",
                                     ""};
    if (!es_alone) {  // the direct path stops by its own rule; the limit is only a bound
      args.push_back("--iterations");
      args.push_back(std::to_string(budget * 2 + 10));
    }
    ASSERT_EQ(wait(spawn(POET_COORDINATOR_BIN, args, name)), 0) << read(root_ / (name + ".err"));
    std::string report_json;
    ASSERT_EQ(report({"--run-dir", dir.string(), "--json", "-", "--coverage-per-level", "5"}, &report_json, &err), 0)
        << err;
    const nlohmann::json j = nlohmann::json::parse(report_json);
    EXPECT_LE(j["pairs"][0]["es_steps"].get<int>(), budget);
  }
  EXPECT_NE(tool(POET_LINEAGE_BIN,
                 {"--run-dir", run.string(), "--pair", "1", "--es-alone-config", "--direct-path-config"}, &text, &err),
            0);

  // Figure 3's table and rose
  const fs::path rose = root_ / "rose.png";
  ASSERT_EQ(tool(POET_CONTROLS_BIN,
                 {"--run-dir", run.string(), "--pair", "1", (root_ / "--es-alone-config").string(),
                  (root_ / "--direct-path-config").string(), "--json", "-", "--rose", rose.string()},
                 &text, &err),
            0)
      << err;
  const nlohmann::json j = nlohmann::json::parse(text);
  EXPECT_EQ(j["poet"]["lineage_es_steps"].get<int>(), budget);
  EXPECT_EQ(j["poet"]["lineage_env_steps"].get<int64_t>(), lineage_env_steps);
  ASSERT_EQ(j["controls"].size(), 2u);
  EXPECT_EQ(j["controls"][0]["mode"], "ES alone");
  EXPECT_EQ(j["controls"][1]["mode"], "direct path");
  for (const auto& control : j["controls"]) {
    EXPECT_EQ(control["seed"].get<int>(), 9);
    EXPECT_LE(control["es_steps"].get<int>(), budget);
    EXPECT_GT(control["env_steps"].get<int64_t>(), 0);
    // a solved control's closest environment is at distance 0 exactly when it solved the target
    if (!control["normalized_distance"].is_null()) {
      EXPECT_EQ(control["normalized_distance"].get<double>() == 0, !control["solved_at_es_step"].is_null()) << control;
    }
  }
  EXPECT_EQ(read(rose).substr(1, 3), "PNG");
  // the table for people; a control of another environment is refused
  ASSERT_EQ(tool(POET_CONTROLS_BIN, {"--run-dir", run.string(), "--pair", "1", (root_ / "--es-alone-config").string()},
                 &text, &err),
            0)
      << err;
  EXPECT_TRUE(contains(text, "| ES alone | 9 | ")) << text;
  EXPECT_NE(tool(POET_CONTROLS_BIN, {"--run-dir", run.string(), "--pair", "0", (root_ / "--es-alone-config").string()},
                 &text, &err),
            0);
  EXPECT_TRUE(contains(err, "its target is not the pair's environment")) << err;
}

TEST_F(ReportProcessTest, ReportsALiveRunAsOfItsLastCheckpoint) {
  std::ofstream(config_) << config_with("iterations: 6", "iterations: 100000");
  const fs::path run = root_ / "live";
  const pid_t pid = coordinator(run, {"--threads", "1"}, "live");
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  int reported = 0, live = 0, last = -1;
  while (reported < 5 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(200ms);
    if (!fs::exists(run / "checkpoint.pb")) continue;
    std::string out, err;
    ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "5"}, &out, &err), 0) << err;
    const nlohmann::json j = nlohmann::json::parse(out);
    EXPECT_GE(j["iterations_done"].get<int>(), last);  // never goes back
    last = j["iterations_done"].get<int>();
    live += j["live"].get<bool>() ? 1 : 0;
    reported += 1;
  }
  EXPECT_EQ(reported, 5);
  EXPECT_EQ(live, 5);
  // the run went on undisturbed and stops as a run interrupted by SIGTERM does (143), with its checkpoint
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait(pid), 143) << read(root_ / "live.err");
  std::string out;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", "-", "--coverage-per-level", "5"}, &out), 0);
  EXPECT_EQ(nlohmann::json::parse(out)["live"], false);
}

TEST_F(ReportProcessTest, BadRunDirectoriesGetAClearMessageAndExitTwo) {
  const fs::path good = threads_run();
  const auto copy = [&](const std::string& name) {
    const fs::path dir = root_ / name;
    fs::copy(good, dir, fs::copy_options::recursive);
    return dir;
  };
  const auto expect_error = [&](const fs::path& dir, const std::string& message) {
    const auto before = fs::exists(dir) ? files_of(dir) : decltype(files_of(dir)){};
    std::string err;
    EXPECT_EQ(report({"--run-dir", dir.string()}, nullptr, &err), 2) << dir;
    EXPECT_TRUE(contains(err, message)) << "expected \"" << message << "\" in: " << err;
    if (fs::exists(dir)) {
      EXPECT_TRUE(before == files_of(dir)) << dir << " changed";
    }
  };
  expect_error(root_ / "absent", "no such directory");
  fs::create_directories(root_ / "empty");
  expect_error(root_ / "empty", "is not a run directory");
  const fs::path starting = root_ / "starting";
  fs::create_directories(starting);
  fs::copy_file(good / "config.textproto", starting / "config.textproto");
  expect_error(starting, "has not saved its first checkpoint");

  const auto patch = [](const fs::path& file, size_t offset, char value) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(offset));
    f.put(value);
  };
  const fs::path damaged = copy("damaged");
  patch(damaged / "checkpoint.pb", 200, '\x5a');
  expect_error(damaged, "checksum");
  const fs::path newer = copy("newer");
  patch(newer / "checkpoint.pb", 8, '\x02');  // format version 2
  expect_error(newer, "format version 2");
  const fs::path truncated = copy("truncated");
  fs::resize_file(truncated / "events.jsonl", fs::file_size(truncated / "events.jsonl") / 2);
  expect_error(truncated, "truncated or damaged");
  const fs::path garbled = copy("garbled");
  patch(garbled / "events.jsonl", 0, '#');
  expect_error(garbled, "events.jsonl: its first");  // the checkpoint's CRC-32 of the log finds it
  expect_error(garbled, "CRC-32 mismatch");
  const fs::path no_stats = copy("no_stats");
  fs::remove(no_stats / "pair_stats.csv");
  expect_error(no_stats, "pair_stats.csv: cannot read");

  // outputs inside the run directory are refused before anything is read or written
  const auto before = files_of(good);
  std::string err;
  EXPECT_EQ(report({"--run-dir", good.string(), "--plots", (good / "plots").string()}, nullptr, &err), 2);
  EXPECT_TRUE(contains(err, "inside the run directory")) << err;
  EXPECT_EQ(report({"--run-dir", good.string(), "--json", (good / "r.json").string()}, nullptr, &err), 2);
  EXPECT_TRUE(before == files_of(good));
  EXPECT_EQ(report({"--run-dir", good.string(), "--target", (root_ / "nope.env.json").string()}, nullptr, &err), 2);
  EXPECT_TRUE(contains(err, "--target")) << err;
}

TEST_F(ReportProcessTest, PicturesOfEveryKindFromARunDirectoryWithoutChangingIt) {
  const fs::path run = walker_run();
  const auto before = files_of(run);
  const fs::path out = root_ / "pictures";
  fs::create_directories(out);
  for (const auto& [kind, file, pair] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"scores", "scores.png", ""},
                                                                      {"levels", "levels.svg", ""},
                                                                      {"annecs", "annecs.png", ""},
                                                                      {"tree", "tree.png", ""},
                                                                      {"rose", "rose.svg", ""},
                                                                      {"course", "course.png", "1"},
                                                                      {"filmstrip", "filmstrip.svg", "2"},
                                                                      {"walk", "walk.gif", "1"},
                                                                      {"lineage", "lineage.png", "2"}}) {
    std::vector<std::string> args = {"picture", kind, (out / file).string(), "--run-dir", run.string()};
    if (!pair.empty()) args.insert(args.end(), {"--pair", pair});
    std::string err;
    ASSERT_EQ(poetctl(args, nullptr, &err), 0) << kind << ": " << err;
    const std::string bytes = read(out / file);
    if (file.ends_with(".png")) {
      EXPECT_TRUE(is_png(bytes)) << file;
    }
    if (file.ends_with(".svg")) {
      EXPECT_TRUE(is_svg(bytes)) << file;
    }
    if (file.ends_with(".gif")) {
      EXPECT_TRUE(is_gif(bytes)) << file;
    }
  }
  EXPECT_TRUE(before == files_of(run)) << "the run directory changed";

  // bad requests: a clear message and a non-zero exit, nothing written
  const auto refused = [&](std::vector<std::string> args, const std::string& message) {
    std::string err;
    EXPECT_NE(poetctl(args, nullptr, &err), 0) << message;
    EXPECT_TRUE(contains(err, message)) << "expected \"" << message << "\" in: " << err;
  };
  refused({"picture", "course", (out / "x.png").string(), "--pair", "99", "--run-dir", run.string()}, "no pair 99");
  refused({"picture", "walk", (out / "x.png").string(), "--pair", "1", "--run-dir", run.string()}, "GIF");
  refused({"picture", "tree", (out / "x.png").string(), "--pair", "1", "--run-dir", run.string()}, "no --pair");
  refused({"picture", "course", (out / "x.png").string(), "--run-dir", run.string()}, "give --pair");
  refused({"picture", "bogus", (out / "x.png").string(), "--run-dir", run.string()}, "one of scores");
  fs::create_directories(root_ / "empty");
  refused({"picture", "tree", (out / "x.png").string(), "--run-dir", (root_ / "empty").string()},
          "is not a run directory");
  const fs::path damaged = root_ / "damaged";
  fs::copy(run, damaged, fs::copy_options::recursive);
  {
    std::fstream f(damaged / "checkpoint.pb", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(300);
    f.put('\x17');
  }
  refused({"picture", "tree", (out / "x.png").string(), "--run-dir", damaged.string()}, "checksum");
  refused({"picture", "tree", (run / "tree.png").string(), "--run-dir", run.string()}, "inside the run directory");
  EXPECT_FALSE(fs::exists(out / "x.png"));
  EXPECT_TRUE(before == files_of(run));
}

// A CPPN run is read and drawn by every tool: its environment files hold the genome, the report reads the run,
// pictures draw its courses, and poet-eval and poet-rollout run walkers on its environment files.
TEST_F(ReportProcessTest, ACppnRunIsReadAndDrawnByEveryTool) {
  const fs::path run = walker_run(kCppnWalkerConfig, "cppn");
  const auto before = files_of(run);
  const std::string env_file = (run / "envs" / "pair-1.env.json").string();
  ASSERT_TRUE(fs::exists(env_file)) << "no child was admitted";
  EXPECT_TRUE(contains(read(env_file), "\"cppn\": {")) << read(env_file);
  EXPECT_TRUE(contains(read(run / "events.jsonl"), "cppn-")) << "environments are named by their genome";

  std::string out, err;
  ASSERT_EQ(report({"--run-dir", run.string(), "--json", (root_ / "cppn.json").string()}, &out, &err), 0) << err;
  const nlohmann::json j = nlohmann::json::parse(read(root_ / "cppn.json"));
  EXPECT_GE(j["pairs"].size(), 2u);
  for (const auto& [kind, file] : std::vector<std::pair<std::string, std::string>>{{"course", "course.png"},
                                                                                   {"filmstrip", "filmstrip.svg"},
                                                                                   {"walk", "walk.gif"},
                                                                                   {"lineage", "lineage.svg"}}) {
    ASSERT_EQ(
        poetctl({"picture", kind, (root_ / file).string(), "--run-dir", run.string(), "--pair", "1"}, nullptr, &err), 0)
        << kind << ": " << err;
  }
  EXPECT_TRUE(is_png(read(root_ / "course.png")));
  EXPECT_TRUE(is_svg(read(root_ / "filmstrip.svg")));
  EXPECT_TRUE(is_gif(read(root_ / "walk.gif")));
  EXPECT_TRUE(contains(read(root_ / "lineage.svg"), "<svg"));  // the first environment and pair 1, one above the other

  const std::string policy = (run / "policies" / "pair-1.json").string();
  ASSERT_EQ(tool(POET_EVAL_BIN, {"--policy", policy, "--env", env_file, "--seeds", "0:1"}, &out, &err), 0) << err;
  EXPECT_TRUE(contains(out, "cppn-")) << out;
  ASSERT_EQ(
      tool(POET_ROLLOUT_BIN, {"--policy", policy, "--env", env_file, "--max-steps", "50", "--picture", ""}, &out, &err),
      0)
      << err;
  EXPECT_TRUE(contains(out, "return ")) << out;

  // the controls: ES alone on a CPPN course, but no direct path to one
  ASSERT_EQ(tool(POET_LINEAGE_BIN, {"--run-dir", run.string(), "--pair", "1", "--es-alone-config"}, &out, &err), 0)
      << err;
  EXPECT_TRUE(contains(out, "cppn {")) << out;
  EXPECT_FALSE(contains(out, "environments:")) << out;
  EXPECT_EQ(tool(POET_LINEAGE_BIN, {"--run-dir", run.string(), "--pair", "1", "--direct-path-config"}, &out, &err), 2);
  EXPECT_TRUE(contains(err, "no direct path")) << err;
  EXPECT_TRUE(before == files_of(run)) << "the run directory changed";
}

TEST_F(ReportProcessTest, PicturesFromALiveCoordinatorsStatusSocket) {
  std::ofstream(config_) << config_with("iterations: 6", "iterations: 100000");
  const fs::path run = root_ / "live";
  const pid_t pid = coordinator(run, {"--threads", "1"}, "live");
  const std::string port = await_log("live", "status: http://127\\.0\\.0\\.1:([0-9]+)/status");
  ASSERT_FALSE(port.empty());
  const std::string address = "127.0.0.1:" + port;
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (!fs::exists(run / "checkpoint.pb") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(50ms);
  for (const auto& [kind, file, pair] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"tree", "tree.svg", ""},
                                                                      {"scores", "scores.png", ""},
                                                                      {"walk", "walk.gif", "0"},
                                                                      {"lineage", "lineage.svg", "0"}}) {
    std::vector<std::string> args = {"--address", address, "picture", kind, (root_ / file).string()};
    if (!pair.empty()) args.insert(args.end(), {"--pair", pair});
    std::string err;
    ASSERT_EQ(poetctl(args, nullptr, &err), 0) << kind << ": " << err;
  }
  EXPECT_TRUE(is_svg(read(root_ / "tree.svg")));
  EXPECT_TRUE(is_png(read(root_ / "scores.png")));
  EXPECT_TRUE(is_gif(read(root_ / "walk.gif")));
  EXPECT_TRUE(contains(read(root_ / "lineage.svg"), "<svg"));  // the first environment alone
  std::string err;
  EXPECT_EQ(
      poetctl({"--address", address, "picture", "course", (root_ / "c.svg").string(), "--pair", "4242"}, nullptr, &err),
      1);
  EXPECT_TRUE(contains(err, "404")) << err;
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  EXPECT_EQ(wait(pid), 143);
  // the coordinator gone: a clear message, not a hang
  EXPECT_EQ(poetctl({"--address", address, "picture", "tree", (root_ / "t.svg").string()}, nullptr, &err), 1);
  EXPECT_TRUE(contains(err, "cannot reach the coordinator")) << err;
}

}  // namespace
}  // namespace poet::testing
