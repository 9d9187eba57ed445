// Tests coordinator/status/status_board.cpp and the renderers it serves through (status_messages.cpp,
// prometheus_text.cpp, status_json.cpp): what publish_run and publish_dispatch put on the board comes out in
// every message as well-formed JSON; rates and ages follow a fake clock; events and scores are read from the run
// directory's files (whole lines only); /metrics is Prometheus text format.

#include "coordinator/status/status_board.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <thread>

#include "../../engine/engine_test_support.h"
#include "common/text/utf8.h"
#include "coordinator/status/status_json.h"
#include "run_directory/files/run_directory.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using nlohmann::json;
using SteadyTime = std::chrono::steady_clock::time_point;

// A clock the test moves by hand.
struct FakeClock {
  SteadyTime now = SteadyTime(1000s);
  StatusBoard::Clock function() {
    return [this] { return now; };
  }
};

// Three pairs: 0 (retired at 9), 1 child of 0 (solved at 7), 2 child of 1 with two accepted transfers.
RunState three_pairs() {
  RunState state = testing::state_at(testing::tiny_config(), 12, 120.0);
  Pair& first = state.pairs[0];
  first.retired_iteration = 9;
  first.es_steps = 9;
  Pair& second = testing::add_pair(state, testing::rough(4.6, 21), 240.0);
  second.parent_id = 0;
  second.created_iteration = 4;
  second.first_solved_iteration = 7;
  second.best_score = 251.5;
  second.best_iteration = 8;
  second.es_steps = 8;
  Pair& third = testing::add_pair(state, testing::rough(1.0, 33), 60.0);
  third.parent_id = 1;
  third.created_iteration = 8;
  third.initial_source_pair = 0;
  third.initial_by_proposal = true;
  third.admission_score = 55.0;
  third.transfers = {{10, 1, false, 70.0}, {11, 0, true, 80.0}};
  third.transfer_attempts = 3;
  state.counters.rollouts = 5000;
  state.counters.env_steps = 400'000;
  state.counters.transfer_attempts = 3;
  state.counters.transfer_successes = 2;
  return state;
}

json parse(const google::protobuf::Message& message) {
  const std::string text = status_json(message);
  EXPECT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  return json::parse(text);  // throws, failing the test, on malformed JSON
}

class StatusBoardTest : public ::testing::Test {
 protected:
  void write(const std::string& file, const std::string& text, bool append = false) {
    std::ofstream out(dir_ / file, std::ios::binary | (append ? std::ios::app : std::ios::trunc));
    out << text;
  }

  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
  FakeClock clock_;
};

TEST_F(StatusBoardTest, BeforeAnyPublishTheBoardIsStarting) {
  StatusBoard board(dir_, clock_.function());
  const json status = parse(board.status());
  EXPECT_EQ(status["state"], "starting");
  EXPECT_EQ(status["run_dir"], dir_.string());
  EXPECT_EQ(status["iteration"], 0);
  EXPECT_EQ(status["workers"], 0);
  EXPECT_TRUE(parse(board.pairs()).contains("pairs"));
  EXPECT_FALSE(board.pair(0).has_value());
  EXPECT_FALSE(board.has_pair(0));
  EXPECT_EQ(parse(board.workers())["workers"].size(), 0u);
  EXPECT_EQ(parse(board.archive())["pairs"].size(), 0u);
}

TEST_F(StatusBoardTest, StatusSaysWhatWasPublished) {
  StatusBoard board(dir_, clock_.function());
  board.publish_run(three_pairs(), 10);
  board.set_state(RunPhase::kWaitingForWorkers, "no worker yet");
  const json s = parse(board.status());
  EXPECT_EQ(s["mode"], "POET");
  EXPECT_EQ(s["seed"], "3");  // 64-bit integers are JSON strings in protobuf's mapping
  EXPECT_EQ(s["iteration"], 12);
  EXPECT_EQ(s["iterations"], 100);
  EXPECT_EQ(s["finished"], false);
  EXPECT_EQ(s["pairs_created"], 3);
  EXPECT_EQ(s["pairs_active"], 2);
  EXPECT_EQ(s["pairs_solved"], 1);
  EXPECT_EQ(s["rollouts"], "5000");
  EXPECT_EQ(s["env_steps"], "400000");
  EXPECT_EQ(s["transfer_successes"], "2");
  EXPECT_EQ(s["last_checkpoint_iteration"], 10);
  EXPECT_EQ(s["state"], "waiting_for_workers");
  EXPECT_EQ(s["note"], "no worker yet");
  // every field of the contract is printed, zeros included
  for (const char* field : {"run_dir",         "mode",         "seed",
                            "iteration",       "iterations",   "finished",
                            "pairs_created",   "pairs_active", "pairs_solved",
                            "workers",         "queue_depth",  "in_flight_jobs",
                            "rollouts",        "env_steps",    "rollouts_per_s",
                            "env_steps_per_s", "uptime_s",     "last_checkpoint_iteration",
                            "state",           "note"})
    EXPECT_TRUE(s.contains(field)) << field;
  for (const char* field : {"transfer_attempts", "transfer_successes", "annecs_at_admission", "annecs_at_archiving"})
    EXPECT_TRUE(s.contains(field)) << field;
}

TEST_F(StatusBoardTest, PairsAndArchiveListEveryPair) {
  StatusBoard board(dir_, clock_.function());
  board.publish_run(three_pairs(), 10);
  const json pairs = parse(board.pairs())["pairs"];
  ASSERT_EQ(pairs.size(), 3u);
  EXPECT_EQ(pairs[0]["id"], 0);
  EXPECT_EQ(pairs[0]["active"], false);
  EXPECT_EQ(pairs[0]["retired_iteration"], 9);
  EXPECT_EQ(pairs[0]["parent_id"], -1);
  EXPECT_EQ(pairs[1]["solved"], true);
  EXPECT_EQ(pairs[1]["first_solved_iteration"], 7);
  EXPECT_EQ(pairs[1]["best_score"], 251.5);
  EXPECT_EQ(pairs[1]["env"], testing::rough(4.6).encoding.name);
  EXPECT_EQ(pairs[1]["seed"], 21);
  EXPECT_EQ(pairs[1]["encoding"]["roughness"], 4.6);
  EXPECT_EQ(pairs[1]["difficulty"], "challenging");  // roughness >= 4.5 is one Table 1 condition
  EXPECT_EQ(pairs[1]["difficulty_level"], 1);
  EXPECT_EQ(pairs[2]["difficulty"], "easy");
  EXPECT_EQ(pairs[2]["es_steps"], "0");

  const json archive = parse(board.archive())["pairs"];
  ASSERT_EQ(archive.size(), 3u);
  EXPECT_EQ(archive[0]["active"], false);
  EXPECT_EQ(archive[2]["active"], true);
  EXPECT_EQ(archive[2]["encoding"]["roughness"], 1.0);
  EXPECT_EQ(archive[2]["seed"], 33);
}

TEST_F(StatusBoardTest, ACppnPairCarriesItsGenomeAndNoTableOneLevel) {
  RunState state = three_pairs();
  EnvDef cppn{{}, 5};
  cppn.encoding.cppn = std::make_shared<const CppnGenome>(cppn_seed_genome(0.25, -0.5));
  cppn.encoding.name = cppn_name(*cppn.encoding.cppn);
  testing::add_pair(state, cppn, 80.0);
  StatusBoard board(dir_, clock_.function());
  board.publish_run(state, 10);
  const json pair = parse(board.pairs())["pairs"][3];
  EXPECT_EQ(pair["env"], cppn.encoding.name);
  EXPECT_EQ(pair["difficulty"], "CPPN terrain");
  EXPECT_EQ(pair["encoding"]["cppn"]["connections"][0]["weight"], 0.25);
  EXPECT_EQ(pair["encoding"]["cppn"]["nodes"][1]["bias"], -0.5);
}

TEST_F(StatusBoardTest, PairDetailHasLineageAndScoresFromTheCsv) {
  write(kStatsFile, pair_stats_header());
  for (int t = 8; t < 12; ++t) {
    for (int id : {1, 2}) {
      PairStatsRow row;
      row.iteration = t;
      row.pair = id;
      row.env = "odd, \"name\"";  // quoted in the file
      row.score = 10.0 * t + id;
      row.best_score = 100.0 + t;
      write(kStatsFile, pair_stats_row(row), true);
    }
  }
  StatusBoard board(dir_, clock_.function());
  board.publish_run(three_pairs(), 10);
  const std::optional<status::PairDetail> detail = board.pair(2);
  ASSERT_TRUE(detail.has_value());
  const json d = parse(*detail);
  EXPECT_EQ(d["pair"]["id"], 2);
  EXPECT_EQ(d["lineage"]["ancestors"], json::array({1, 0}));
  EXPECT_EQ(d["lineage"]["initial_source_pair"], 0);
  EXPECT_EQ(d["lineage"]["initial_by_proposal"], true);
  EXPECT_EQ(d["lineage"]["admission_score"], 55.0);
  EXPECT_EQ(d["lineage"]["transfer_attempts"], "3");
  ASSERT_EQ(d["lineage"]["transfers"].size(), 2u);
  EXPECT_EQ(d["lineage"]["transfers"][1]["iteration"], 11);
  EXPECT_EQ(d["lineage"]["transfers"][1]["source_pair"], 0);
  EXPECT_EQ(d["lineage"]["transfers"][1]["proposal"], true);
  ASSERT_EQ(d["scores"].size(), 4u);
  EXPECT_EQ(d["scores"][0]["iteration"], 8);
  EXPECT_EQ(d["scores"][0]["score"], 82.0);
  EXPECT_EQ(d["scores"][3]["best_score"], 111.0);
  EXPECT_TRUE(parse(*board.pair(0))["lineage"]["ancestors"].empty());
  EXPECT_FALSE(board.pair(3).has_value());
  EXPECT_TRUE(board.has_pair(0));
  EXPECT_TRUE(board.has_pair(2));
  EXPECT_FALSE(board.has_pair(3));
  EXPECT_FALSE(board.has_pair(-1));

  // rows appended later are read on; a partial last line waits for its newline
  PairStatsRow row;
  row.iteration = 12;
  row.pair = 2;
  row.score = 1.5;
  row.best_score = 111.0;
  const std::string line = pair_stats_row(row);
  write(kStatsFile, line.substr(0, 5), true);
  EXPECT_EQ(board.pair(2)->scores_size(), 4);
  write(kStatsFile, line.substr(5), true);
  ASSERT_EQ(board.pair(2)->scores_size(), 5);
  EXPECT_EQ(board.pair(2)->scores(4).score(), 1.5);
  EXPECT_EQ(board.pair(1)->scores_size(), 4);
}

TEST_F(StatusBoardTest, ThePublishedCopyDoesNotFollowTheState) {
  StatusBoard board(dir_, clock_.function());
  RunState state = three_pairs();
  board.publish_run(state, 10);
  state.pairs[1].best_score = -1;
  state.next_iteration = 99;
  EXPECT_EQ(board.status().iteration(), 12);
  EXPECT_EQ(board.pair(1)->pair().best_score(), 251.5);
}

TEST_F(StatusBoardTest, RatesAreMeasuredOverTheLastPublishes) {
  StatusBoard board(dir_, clock_.function());
  RunState state = three_pairs();
  state.counters.rollouts = 0;
  state.counters.env_steps = 0;
  board.publish_run(state, 0);
  EXPECT_EQ(board.status().rollouts_per_s(), 0);  // one sample: no rate yet

  clock_.now += 2s;
  state.counters.rollouts = 100;
  state.counters.env_steps = 1000;
  board.publish_run(state, 0);
  EXPECT_DOUBLE_EQ(board.status().rollouts_per_s(), 50);
  EXPECT_DOUBLE_EQ(board.status().env_steps_per_s(), 500);

  // a slow start then a fast stretch: only the last kRateWindow publishes count
  for (size_t i = 0; i < kRateWindow; ++i) {
    clock_.now += 1s;
    state.counters.rollouts += 10;
    state.counters.env_steps += 1000;
    board.publish_run(state, 0);
  }
  EXPECT_DOUBLE_EQ(board.status().rollouts_per_s(), 10);
  EXPECT_DOUBLE_EQ(board.status().env_steps_per_s(), 1000);

  // counters that go back (another state) start the window over
  state.counters.rollouts = 5;
  board.publish_run(state, 0);
  EXPECT_EQ(board.status().rollouts_per_s(), 0);
}

TEST_F(StatusBoardTest, UptimeAndHeartbeatAgesFollowTheClock) {
  StatusBoard board(dir_, clock_.function());
  DispatchView dispatch;
  dispatch.at = 10'000;  // the dispatcher's clock: a-worker was last heard 1.5 s before
  WorkerView a;  // a view's standing is trust's: only what the dispatcher knows is set here
  a.id = "worker-a";
  a.name = "10.0.0.2";
  a.threads = 4;
  a.fingerprint_digest = 0x00ab'cdef'0123'4567ULL;
  a.jobs_done = 12;
  a.results_done = 11;
  a.last_heard = 8'500;
  WorkerView b;
  b.id = std::string("\x00\x01\xfe", 3);
  b.threads = 1;
  b.fingerprint_digest = 1;
  b.last_heard = 10'000;
  dispatch.workers = {a, b};
  dispatch.queue_depth = 7;
  dispatch.in_flight_jobs = 3;
  dispatch.dropped_frames = {{"malformed", 2}};
  board.publish_dispatch(dispatch);
  clock_.now += 2s;

  const json w = parse(board.workers());
  ASSERT_EQ(w["workers"].size(), 2u);
  EXPECT_EQ(w["workers"][0]["id"], "worker-a");
  EXPECT_EQ(w["workers"][0]["address"], "10.0.0.2");
  EXPECT_EQ(w["workers"][0]["threads"], 4);
  EXPECT_EQ(w["workers"][0]["jobs_done"], "12");
  EXPECT_DOUBLE_EQ(w["workers"][0]["seconds_since_heartbeat"].get<double>(), 3.5);
  EXPECT_EQ(w["workers"][0]["fingerprint_digest"], "00abcdef01234567");
  EXPECT_EQ(w["workers"][1]["id"], "0x0001fe");  // a binary routing id, in hex
  EXPECT_EQ(w["queue_depth"], "7");
  EXPECT_EQ(w["dropped_frames"]["malformed"], "2");

  const status::Status s = board.status();
  EXPECT_DOUBLE_EQ(s.uptime_s(), 2.0);
  EXPECT_EQ(s.workers(), 2);
  EXPECT_EQ(s.queue_depth(), 7);
  EXPECT_EQ(s.in_flight_jobs(), 3);
}

TEST_F(StatusBoardTest, EventsAreReadFromEventsJsonlByLine) {
  StatusBoard board(dir_, clock_.function());
  // no file yet: no events
  Expected<status::EventList> none = board.events(0);
  ASSERT_TRUE(none) << none.error();
  EXPECT_EQ(none->events_size(), 0);
  EXPECT_EQ(none->next(), 0);

  write(kEventsFile,
        "{\"iteration\":0,\"event\":\"pair_created\",\"pair\":0,\"env\":\"flat\"}\n"
        "{\"iteration\":4,\"event\":\"transfer\",\"target\":1,\"score\":12.5}\n"
        "not json\n"
        "{\"iteration\":7,\"event\":\"solved\",\"pa");  // being written: not yet an event
  Expected<status::EventList> all = board.events(0);
  ASSERT_TRUE(all) << all.error();
  ASSERT_EQ(all->events_size(), 3);
  EXPECT_EQ(all->next(), 3);
  EXPECT_FALSE(all->more());
  const json j = parse(*all);
  EXPECT_EQ(j["since"], "0");
  EXPECT_EQ(j["events"][0]["event"], "pair_created");
  EXPECT_EQ(j["events"][0]["iteration"], 0);
  EXPECT_EQ(j["events"][1]["score"], 12.5);
  EXPECT_EQ(j["events"][2]["unparsed"], "not json");

  // pages
  Expected<status::EventList> page = board.events(1, 1);
  ASSERT_TRUE(page);
  ASSERT_EQ(page->events_size(), 1);
  EXPECT_EQ(page->next(), 2);
  EXPECT_TRUE(page->more());
  EXPECT_EQ(page->events(0).fields().at("event").string_value(), "transfer");
  Expected<status::EventList> beyond = board.events(10);
  ASSERT_TRUE(beyond);
  EXPECT_EQ(beyond->events_size(), 0);
  EXPECT_EQ(beyond->next(), 10);

  // the line completes
  write(kEventsFile, "ir\":1}\n", true);
  Expected<status::EventList> later = board.events(3);
  ASSERT_TRUE(later);
  ASSERT_EQ(later->events_size(), 1);
  EXPECT_EQ(later->events(0).fields().at("pair").number_value(), 1);
  EXPECT_EQ(later->next(), 4);
}

TEST_F(StatusBoardTest, MetricsAreInPrometheusTextFormat) {
  StatusBoard board(dir_, clock_.function());
  board.publish_run(three_pairs(), 10);
  DispatchView dispatch;
  dispatch.workers.resize(2);
  dispatch.queue_depth = 5;
  dispatch.in_flight_jobs = 4;
  dispatch.dropped_frames = {{"wrong_fingerprint", 3}, {"bad_result", 1}};
  board.publish_dispatch(dispatch);
  EXPECT_TRUE(board.metrics_text().find("\npoet_skipped_key_files_total 0\n") != std::string::npos);
  board.count_skipped_key_file();
  board.count_skipped_key_file();
  board.publish_cache(7, 1234);
  board.publish_phases({1.5, 20.25, 0.5, 3}, 18.5);
  const std::string text = board.metrics_text();
  EXPECT_NE(text.find("\npoet_cached_episodes_total 7\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\npoet_cached_env_steps_total 1234\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\npoet_phase_seconds_total{phase=\"es_steps\"} 20.250\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\npoet_phase_seconds_total{phase=\"transfer\"} 3.000\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\npoet_waiting_seconds_total 18.500\n"), std::string::npos) << text;

  // every line is a HELP, a TYPE or a sample of the family just announced
  const std::regex help(R"(# HELP (poet_[a-z_]+) \S.*)");
  const std::regex type(R"(# TYPE (poet_[a-z_]+) (gauge|counter))");
  const std::regex sample(
      R"((poet_[a-z_]+)(\{(reason|definition|phase|measure)="[a-z_]+"(,among="[a-z]+")?\})? (-?[0-9]+(\.[0-9]+)?))");
  std::istringstream lines(text);
  std::string line, family;
  std::map<std::string, std::string> values;
  int families = 0;
  std::smatch m;
  while (std::getline(lines, line)) {
    if (std::regex_match(line, m, help)) {
      family = m[1];
      ++families;
      ASSERT_TRUE(std::getline(lines, line));
      ASSERT_TRUE(std::regex_match(line, m, type)) << line;
      EXPECT_EQ(m[1], family);
    } else {
      ASSERT_TRUE(std::regex_match(line, m, sample)) << line;
      EXPECT_EQ(m[1], family) << line;
      values[m[1].str() + m[2].str()] = m[5];
    }
  }
  EXPECT_EQ(text.back(), '\n');
  EXPECT_GE(families, 8);
  EXPECT_EQ(values["poet_iteration"], "12");
  EXPECT_EQ(values["poet_pairs_active"], "2");
  EXPECT_EQ(values["poet_rollouts_total"], "5000");
  EXPECT_EQ(values["poet_env_steps_total"], "400000");
  EXPECT_EQ(values["poet_workers"], "2");
  EXPECT_EQ(values["poet_queue_depth"], "5");
  EXPECT_EQ(values["poet_in_flight_jobs"], "4");
  EXPECT_EQ(values["poet_dropped_frames_total{reason=\"wrong_fingerprint\"}"], "3");
  EXPECT_EQ(values["poet_dropped_frames_total{reason=\"malformed\"}"], "0");   // every known reason, from the start
  EXPECT_EQ(values["poet_dropped_frames_total{reason=\"bad_result\"}"], "1");  // and any other counted
  EXPECT_EQ(values["poet_skipped_key_files_total"], "2");
  EXPECT_EQ(values["poet_annecs{definition=\"at_admission\"}"], "1");
  EXPECT_EQ(values["poet_annecs{definition=\"at_archiving\"}"], "0");
  EXPECT_TRUE(text.find("# TYPE poet_rollouts_total counter\n") != std::string::npos);
}

// Both ANNECS definitions, named in /status and /metrics: the first pair is not a child, so it counts at archiving
// (retired at 9, solved by then) but never at admission; pair 1 counts at admission from its solve.
TEST_F(StatusBoardTest, AnnecsInBothDefinitions) {
  StatusBoard board(dir_, clock_.function());
  RunState state = three_pairs();
  board.publish_run(state, 10);
  json s = parse(board.status());
  EXPECT_EQ(s["annecs_at_admission"], 1);
  EXPECT_EQ(s["annecs_at_archiving"], 0);  // the retired pair was never solved

  state.pairs[0].first_solved_iteration = 2;
  board.publish_run(state, 10);
  s = parse(board.status());
  EXPECT_EQ(s["annecs_at_admission"], 1);
  EXPECT_EQ(s["annecs_at_archiving"], 1);
  const std::string text = board.metrics_text();
  for (const char* line : {"# TYPE poet_annecs gauge\n", "\npoet_annecs{definition=\"at_admission\"} 1\n",
                           "\npoet_annecs{definition=\"at_archiving\"} 1\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line;
  const size_t help = text.find("# HELP poet_annecs ");
  ASSERT_NE(help, std::string::npos);
  const std::string help_line = text.substr(help, text.find('\n', help) - help);
  for (const char* words : {"at_admission: environments admitted by reproduction and solved since",
                            "at_archiving: environments retired that had been solved by then"})
    EXPECT_NE(help_line.find(words), std::string::npos) << help_line;
}

// The obstacle frontier over the solved pairs and over all admitted ones, and the hardest level solved, in /status
// and /metrics: pair 1 (roughness 4.6) is solved, pair 3 (gaps to 6.4, stumps to 2.6) only admitted.
TEST_F(StatusBoardTest, TheObstacleFrontierSolvedAndAdmitted) {
  StatusBoard board(dir_, clock_.function());
  RunState state = three_pairs();
  EnvDef hard = testing::rough(2.0, 44);
  hard.encoding.pit_gap = Interval{1.2, 6.4};
  hard.encoding.stump_width = Interval{1, 2};
  hard.encoding.stump_height = Interval{0.4, 2.6};
  hard.encoding.stump_float = Interval{0, 1};
  testing::add_pair(state, hard, 80.0).created_iteration = 11;
  board.publish_run(state, 12);
  json s = parse(board.status());
  EXPECT_EQ(s["frontier_solved"], json({{"roughness", 4.6}, {"gap_hi", 0.0}, {"stump_hi", 0.0}})) << s.dump();
  EXPECT_EQ(s["frontier_admitted"], json({{"roughness", 4.6}, {"gap_hi", 6.4}, {"stump_hi", 2.6}})) << s.dump();
  EXPECT_EQ(s["highest_level_solved"], "challenging");
  std::string text = board.metrics_text();
  for (const char* line :
       {"\npoet_obstacle_frontier{measure=\"roughness\",among=\"solved\"} 4.6\n",
        "\npoet_obstacle_frontier{measure=\"gap_hi\",among=\"solved\"} 0\n",
        "\npoet_obstacle_frontier{measure=\"stump_hi\",among=\"admitted\"} 2.6\n", "\npoet_highest_level_solved 1\n"})
    EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;

  // the hard pair solved: very challenging (gaps and stumps), the solved frontier at the admitted one
  state.pairs.back().first_solved_iteration = 12;
  board.publish_run(state, 13);
  s = parse(board.status());
  EXPECT_EQ(s["frontier_solved"], s["frontier_admitted"]);
  EXPECT_EQ(s["highest_level_solved"], "very challenging");
  EXPECT_NE(board.metrics_text().find("\npoet_highest_level_solved 2\n"), std::string::npos);

  // nothing solved yet: no level, and -1 in /metrics
  for (Pair& p : state.pairs) p.first_solved_iteration = kNone;
  board.publish_run(state, 13);
  s = parse(board.status());
  EXPECT_EQ(s["highest_level_solved"], "");
  EXPECT_EQ(s["frontier_solved"], json({{"roughness", 0.0}, {"gap_hi", 0.0}, {"stump_hi", 0.0}})) << s.dump();
  EXPECT_NE(board.metrics_text().find("\npoet_highest_level_solved -1\n"), std::string::npos);
}

TEST_F(StatusBoardTest, InvalidUtf8InNamesStillGivesValidJson) {
  StatusBoard board(dir_, clock_.function());
  RunState state = three_pairs();
  state.pairs[1].env.encoding.name = "bad\xff\xfe name \xc3\xa9";
  board.publish_run(state, 10);
  board.set_state(RunPhase::kStopping, "stop \xe2\x82");
  const json pairs = parse(board.pairs());
  EXPECT_EQ(pairs["pairs"][1]["env"], "bad?? name \xc3\xa9");
  EXPECT_EQ(parse(board.status())["note"], "stop ??");
  EXPECT_EQ(valid_utf8("\xed\xa0\x80"), "???");  // a surrogate
}

TEST_F(StatusBoardTest, PublishersAndReadersRunConcurrently) {
  StatusBoard board(dir_);  // the real clock
  const RunState state = three_pairs();
  board.publish_run(state, 0);  // readers only ever see a run of three pairs
  std::atomic<bool> done{false};
  std::thread reader([&] {
    while (!done) {
      EXPECT_FALSE(status_json(board.status()).empty());
      EXPECT_EQ(board.pairs().pairs_size(), 3);
      EXPECT_FALSE(board.metrics_text().empty());
    }
  });
  for (int i = 0; i < 300; ++i) {
    board.publish_run(state, i);
    board.publish_dispatch(
        DispatchView{.workers = {}, .refused = {}, .queue_depth = i, .in_flight_jobs = 0, .dropped_frames = {}});
    board.set_state(RunPhase::kRunning);
  }
  done = true;
  reader.join();
  EXPECT_EQ(board.status().last_checkpoint_iteration(), 299);
}

}  // namespace
}  // namespace poet
