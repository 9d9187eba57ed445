// Tests coordinator/status/prometheus_text.cpp against its table (metric_families.h): the exposition of a populated
// board view holds exactly the declared families, in the declared order, each with its declared HELP and TYPE, and
// each family's samples carry exactly its declared labels, every combination of their declared values once.

#include "coordinator/status/prometheus_text.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../../engine/engine_test_support.h"
#include "coordinator/status/metric_families.h"

namespace poet {
namespace {

// A view with every part present: a run with pairs, a dispatcher with workers and drops, the coordinator's own.
BoardView populated_view() {
  RunState state = testing::state_at(testing::tiny_config(), 12, 120.0);
  testing::add_pair(state, testing::rough(4.6, 21), 240.0);
  auto run = std::make_shared<PublishedRun>();
  run->next_iteration = state.next_iteration;
  run->iterations = 200;
  run->counters = state.counters;
  for (const Pair& pair : state.pairs) run->pairs.push_back({pair, 0});
  run->frontier_solved = {4.6, 0, 0};
  run->highest_level_solved = 0;
  auto dispatch = std::make_shared<DispatchView>();
  dispatch->workers.resize(2);
  dispatch->dropped_frames = {{"wrong_fingerprint", 3}};
  BoardView view;
  view.run = run;
  view.dispatch = dispatch;
  view.cached_episodes = 7;
  view.phase_seconds = {1.5, 20.25, 0.5, 3};
  view.uptime_s = 12.5;
  return view;
}

// One family as the exposition wrote it.
struct WrittenFamily {
  std::string name, help, type;
  std::vector<std::vector<std::pair<std::string, std::string>>> samples;  // each sample's labels, in order
};

std::vector<WrittenFamily> parse(const std::string& text) {
  const std::regex help(R"(# HELP (\S+) (.*))");
  const std::regex type(R"(# TYPE (\S+) (\S+))");
  const std::regex sample(R"(([a-z_]+)(?:\{(.*)\})? \S+)");
  const std::regex label(R"(([a-z_]+)="([^"]*)\"(,|$))");
  std::vector<WrittenFamily> families;
  std::istringstream lines(text);
  std::string line;
  std::smatch m;
  while (std::getline(lines, line)) {
    if (std::regex_match(line, m, help)) {
      families.push_back({m[1], m[2], "", {}});
    } else if (std::regex_match(line, m, type)) {
      EXPECT_FALSE(families.empty()) << line;
      if (families.empty()) continue;
      EXPECT_EQ(m[1], families.back().name);
      families.back().type = m[2];
    } else {
      EXPECT_TRUE(std::regex_match(line, m, sample)) << line;
      EXPECT_FALSE(families.empty()) << line;
      if (families.empty() || m.empty()) continue;
      EXPECT_EQ(m[1], families.back().name) << line;
      std::vector<std::pair<std::string, std::string>> labels;
      const std::string inside = m[2];
      for (std::sregex_iterator it(inside.begin(), inside.end(), label), end; it != end; ++it)
        labels.emplace_back((*it)[1], (*it)[2]);
      families.back().samples.push_back(labels);
    }
  }
  return families;
}

TEST(PrometheusTextTest, TheExpositionHoldsExactlyTheDeclaredFamilies) {
  const std::vector<WrittenFamily> written = parse(prometheus_text(populated_view()));
  ASSERT_EQ(written.size(), std::size(kMetricFamilies));
  for (size_t i = 0; i < written.size(); ++i) {
    const MetricFamily& declared = kMetricFamilies[i];
    EXPECT_EQ(written[i].name, declared.name);
    EXPECT_EQ(written[i].help, declared.help) << declared.name;
    EXPECT_EQ(written[i].type, declared.type) << declared.name;
  }
}

TEST(PrometheusTextTest, EachSampleCarriesTheDeclaredLabelsEveryCombinationOnce) {
  for (const WrittenFamily& family : parse(prometheus_text(populated_view()))) {
    const MetricFamily* declared = nullptr;
    for (const MetricFamily& one : kMetricFamilies)
      if (one.name == family.name) declared = &one;
    ASSERT_NE(declared, nullptr) << family.name;
    // every combination of the declared labels' values
    std::set<std::vector<std::pair<std::string, std::string>>> expected = {{}};
    for (const MetricLabel& label : declared->labels) {
      std::set<std::vector<std::pair<std::string, std::string>>> longer;
      for (const auto& prefix : expected)
        for (std::string_view value : label.values) {
          auto labels = prefix;
          labels.emplace_back(label.name, value);
          longer.insert(labels);
        }
      expected = longer;
    }
    const std::set<std::vector<std::pair<std::string, std::string>>> seen(family.samples.begin(), family.samples.end());
    EXPECT_EQ(seen.size(), family.samples.size()) << family.name << ": a sample written twice";
    EXPECT_EQ(seen, expected) << family.name;
  }
}

TEST(PrometheusTextTest, AViewWithNothingPublishedHasTheSameFamilies) {
  const std::vector<WrittenFamily> empty = parse(prometheus_text(BoardView{}));
  ASSERT_EQ(empty.size(), std::size(kMetricFamilies));
  for (size_t i = 0; i < empty.size(); ++i) EXPECT_EQ(empty[i].name, kMetricFamilies[i].name);
}

TEST(PrometheusTextTest, TheTableIsWellFormed) {
  std::set<std::string_view> names;
  for (const MetricFamily& family : kMetricFamilies) {
    EXPECT_TRUE(names.insert(family.name).second) << family.name << " declared twice";
    EXPECT_TRUE(family.name.starts_with("poet_")) << family.name;
    EXPECT_TRUE(family.type == "gauge" || family.type == "counter") << family.name;
    // Prometheus' naming rule: a counter's name ends in _total
    EXPECT_EQ(family.type == "counter", family.name.ends_with("_total")) << family.name;
    EXPECT_FALSE(family.help.empty()) << family.name;
    EXPECT_EQ(family.help.find('\n'), std::string_view::npos) << family.name;
    for (const MetricLabel& label : family.labels) EXPECT_FALSE(label.values.empty()) << family.name;
  }
}

}  // namespace
}  // namespace poet
