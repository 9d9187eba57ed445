// Tests tools/reference/status_reference.cpp and the committed pages it writes: every route of the table, every
// field of every answer message (and of the messages they hold) and every declared metric with its type, labels
// and HELP are on docs/reference/http.md and docs/reference/metrics.md; each route's example answer is one of its
// answers (JSON parsed strictly into its message with every field protobuf prints, the episode with the writer's
// keys, /metrics lines of declared families, a 200 of the route's content type). (tests/docs/
// check_reference_pages.py checks the pages are the generator's output, with a diff.)

#include "tools/reference/status_reference.h"

#include <google/protobuf/descriptor.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "coordinator/status/metric_families.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
namespace protobuf = google::protobuf;

const fs::path kDocs = fs::path(POET_SOURCE_DIR) / "docs" / "reference";

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in) << path;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The part of a page from the heading "## title" (or "### title") to the next heading of that level or above.
std::string section(const std::string& page, const std::string& heading) {
  const size_t start = page.find("\n" + heading + "\n");
  if (start == std::string::npos) return "";
  const std::string level = heading.substr(0, heading.find(' ') + 1);
  size_t end = page.find("\n## ", start + 1);
  if (level == "### ") end = std::min(end, page.find("\n### ", start + 1));
  return page.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

// Every field of the message as a row of the section's table.
void expect_field_rows(const std::string& text, const protobuf::Descriptor& message, const std::string& where) {
  for (int i = 0; i < message.field_count(); ++i)
    EXPECT_NE(text.find("\n| `" + message.field(i)->name() + "` | "), std::string::npos)
        << where << " lacks " << message.full_name() << "." << message.field(i)->name();
}

const protobuf::Descriptor& message(std::string_view name) {
  const protobuf::Descriptor* found =
      protobuf::DescriptorPool::generated_pool()->FindMessageTypeByName("poet.status." + std::string(name));
  EXPECT_NE(found, nullptr) << name;
  return *found;
}

// Every route's section and every field of its message, and of every status.proto message these hold.
void expect_every_route_and_field(const std::string& page, const std::string& where) {
  std::set<const protobuf::Descriptor*> nested;
  for (const StatusRoute& route : kStatusRoutes) {
    const std::string text = section(page, "## " + std::string(route.title));
    ASSERT_FALSE(text.empty()) << where << " has no section " << route.title;
    EXPECT_NE(text.find("`GET " + std::string(route.pattern) + "`"), std::string::npos) << where << route.pattern;
    EXPECT_NE(text.find(std::string(route.content_type)), std::string::npos) << where << route.pattern;
    for (const QueryParam& param : route.query_params)
      EXPECT_NE(text.find("| `" + std::string(param.name) + "` | " + std::to_string(param.lo) + " to " +
                          std::to_string(param.hi) + " | " + std::to_string(param.fallback) + " | "),
                std::string::npos)
          << where << route.pattern << " " << param.name;
    for (const RouteError& error : route.errors)
      EXPECT_NE(text.find("| " + std::to_string(error.status) + " | "), std::string::npos) << where << route.pattern;
    if (route.message.empty()) continue;
    const protobuf::Descriptor& answer = message(route.message);
    expect_field_rows(text, answer, where + " " + std::string(route.title));
    for (int i = 0; i < answer.field_count(); ++i)
      if (const protobuf::Descriptor* inner = answer.field(i)->message_type();
          inner && !answer.field(i)->is_map() && inner->full_name().starts_with("poet.status."))
        nested.insert(inner);
  }
  // the messages held, and those they hold
  for (std::set<const protobuf::Descriptor*> todo = nested; !todo.empty();) {
    const protobuf::Descriptor* inner = *todo.begin();
    todo.erase(todo.begin());
    expect_field_rows(section(page, "### " + inner->name()), *inner, where + " ### " + inner->name());
    for (int i = 0; i < inner->field_count(); ++i)
      if (const protobuf::Descriptor* deeper = inner->field(i)->message_type();
          deeper && deeper->full_name().starts_with("poet.status.") && nested.insert(deeper).second)
        todo.insert(deeper);
  }
  expect_field_rows(section(page, "## Errors"), message("Error"), where + " ## Errors");
}

std::string generated_http_page() {
  const Expected<std::string> page = http_reference_page(kDocs / "examples");
  EXPECT_TRUE(page) << page.error();
  return page ? *page : "";
}

TEST(StatusReferenceTest, TheGeneratedHttpPageHasEveryRouteAndField) {
  expect_every_route_and_field(generated_http_page(), "generated");
}

TEST(StatusReferenceTest, TheCommittedHttpPageHasEveryRouteAndField) {
  expect_every_route_and_field(read(kDocs / "http.md"), "docs/reference/http.md");
}

TEST(StatusReferenceTest, EveryDeclaredMetricIsOnItsPageWithTypeLabelsAndHelp) {
  const std::string page = read(kDocs / "metrics.md");
  for (const MetricFamily& family : kMetricFamilies) {
    const size_t row = page.find("\n| `" + std::string(family.name) + "` | " + std::string(family.type) + " | ");
    ASSERT_NE(row, std::string::npos) << family.name;
    const std::string line = page.substr(row + 1, page.find('\n', row + 1) - row - 1);
    for (const MetricLabel& label : family.labels) {
      EXPECT_NE(line.find("`" + std::string(label.name) + "`: "), std::string::npos) << family.name;
      for (std::string_view value : label.values)
        EXPECT_NE(line.find("`" + std::string(value) + "`"), std::string::npos) << family.name << " " << value;
    }
    EXPECT_NE(line.find(" | " + std::string(family.help) + " |"), std::string::npos) << family.name;
  }
}

// The PromQL column of the metrics page: each query is evaluated by promtool over docs/reference/examples/
// promql_test.yml, so each must be an expr there.
TEST(StatusReferenceTest, EachPromqlExampleIsEvaluatedByThePromtoolTest) {
  const std::string page = metrics_reference_page();
  const std::string checks = read(kDocs / "examples" / "promql_test.yml");
  const size_t table = page.find("| Question | PromQL |");
  ASSERT_NE(table, std::string::npos);
  std::istringstream rows(page.substr(table));
  int queries = 0;
  for (std::string row; std::getline(rows, row);) {
    const size_t open = row.find(" | `"), close = row.rfind("` |");
    if (open == std::string::npos || close == std::string::npos || close <= open) continue;
    const std::string query = row.substr(open + 4, close - open - 4);
    EXPECT_NE(checks.find("- expr: '" + query + "'\n"), std::string::npos) << query;
    ++queries;
  }
  EXPECT_GE(queries, 5);
}

TEST(StatusReferenceTest, EveryRouteHasAnExampleThatIsOneOfItsAnswers) {
  std::set<std::string> files;
  for (const StatusRoute& route : kStatusRoutes) {
    const fs::path file = kDocs / "examples" / example_file(route);
    ASSERT_TRUE(fs::is_regular_file(file)) << file;
    EXPECT_TRUE(files.insert(example_file(route)).second) << file;
    const std::optional<std::string> problem = example_problem(route, read(file));
    EXPECT_FALSE(problem) << file << ": " << problem.value_or("");
  }
  EXPECT_EQ(files.size(), std::size(kStatusRoutes));
  EXPECT_TRUE(files.count("metrics.txt") && files.count("pair-episode.json") && files.count("run-pictures.txt"));
}

const StatusRoute& route_of(RouteKind kind) {
  for (const StatusRoute& route : kStatusRoutes)
    if (route.kind == kind) return route;
  ADD_FAILURE() << "no route of this kind";
  return kStatusRoutes[0];
}

TEST(StatusReferenceTest, AnExampleOffTheSchemaIsRefused) {
  const StatusRoute& health = route_of(RouteKind::kHealth);
  EXPECT_FALSE(example_problem(health, R"({"ok": true, "state": "running"})"));
  EXPECT_TRUE(example_problem(health, R"({"ok": true, "state": "running", "colour": "blue"})"));  // unknown field
  EXPECT_TRUE(example_problem(health, R"({"state": {"running": 1}})"));                           // wrong type
  EXPECT_TRUE(example_problem(health, R"({"ok": true)"));                                         // not JSON
}

// protobuf's JSON prints every scalar, list and map field even at zero: an example without one is from an older
// schema (a field added to status.proto), and is refused until the examples are captured again.
TEST(StatusReferenceTest, AnExampleMissingAFieldIsRefused) {
  const StatusRoute& health = route_of(RouteKind::kHealth);
  const std::optional<std::string> missing = example_problem(health, R"({"ok": true})");
  ASSERT_TRUE(missing);
  EXPECT_NE(missing->find("Health.state"), std::string::npos) << *missing;
  // in a nested message too: the first pair of the list without its id
  const StatusRoute& pairs = route_of(RouteKind::kPairs);
  nlohmann::json list = nlohmann::json::parse(read(kDocs / "examples" / "pairs.json"));
  ASSERT_FALSE(list["pairs"].empty());
  EXPECT_FALSE(example_problem(pairs, list.dump()));
  list["pairs"][0].erase("id");
  const std::optional<std::string> nested = example_problem(pairs, list.dump());
  ASSERT_TRUE(nested);
  EXPECT_NE(nested->find(".id"), std::string::npos) << *nested;
}

TEST(StatusReferenceTest, AnEpisodeExampleHasExactlyTheWritersKeys) {
  const StatusRoute& episode = route_of(RouteKind::kEpisode);
  nlohmann::json answer = nlohmann::json::parse(read(kDocs / "examples" / "pair-episode.json"));
  EXPECT_FALSE(example_problem(episode, answer.dump()));
  EXPECT_TRUE(example_problem(episode, "[1, 2]"));
  answer["colour"] = "blue";
  EXPECT_TRUE(example_problem(episode, answer.dump()));
  answer.erase("colour");
  answer.erase("frames");
  EXPECT_TRUE(example_problem(episode, answer.dump()));
}

TEST(StatusReferenceTest, AMetricsExampleHoldsDeclaredFamiliesOnly) {
  const StatusRoute& metrics = route_of(RouteKind::kMetrics);
  const MetricFamily& iteration = metric_family("poet_iteration");
  const std::string help = "# HELP poet_iteration " + std::string(iteration.help) + "\n";
  EXPECT_FALSE(example_problem(metrics, help + "# TYPE poet_iteration gauge\npoet_iteration 3\n"));
  EXPECT_FALSE(example_problem(metrics, "poet_annecs{definition=\"at_admission\"} 2\n"));
  EXPECT_TRUE(example_problem(metrics, "poet_colour 3\n"));                                    // no such family
  EXPECT_TRUE(example_problem(metrics, "# TYPE poet_iteration counter\npoet_iteration 3\n"));  // wrong type
  EXPECT_TRUE(example_problem(metrics, "# HELP poet_iteration Something else.\npoet_iteration 3\n"));
  EXPECT_TRUE(example_problem(metrics, help));  // no sample
  EXPECT_TRUE(example_problem(metrics, R"({"ok": true})"));
}

TEST(StatusReferenceTest, ASizeExampleIsA200OfTheRoutesContentType) {
  const StatusRoute& dashboard = route_of(RouteKind::kDashboard);
  const StatusRoute& pictures = route_of(RouteKind::kRunPicture);
  ASSERT_TRUE(pictures.example_path.ends_with(".svg"));
  EXPECT_FALSE(example_problem(dashboard, "200 text/html; charset=utf-8, 22,865 bytes\n"));
  EXPECT_FALSE(example_problem(pictures, "200 image/svg+xml, 865 bytes\n"));
  EXPECT_TRUE(example_problem(pictures, "200 image/png, 19,649 bytes\n"));  // not the example path's type
  EXPECT_TRUE(example_problem(pictures, "503 image/svg+xml, 19,649 bytes\n"));
  EXPECT_TRUE(example_problem(pictures, "200 image/svg+xml, 19649 bytes\n"));
  EXPECT_TRUE(example_problem(dashboard, "200 text/html, 1 bytes\n"));
}

TEST(StatusReferenceTest, AMissingOrBadExampleIsAnErrorNamingIt) {
  const Expected<std::string> none = http_reference_markdown({});
  ASSERT_FALSE(none);
  EXPECT_NE(none.error().find("status.json"), std::string::npos) << none.error();

  poet::testing::ScratchDir scratch;
  for (const StatusRoute& route : kStatusRoutes)
    fs::copy_file(kDocs / "examples" / example_file(route), scratch.path() / example_file(route));
  ASSERT_TRUE(http_reference_page(scratch.path()));
  std::ofstream(scratch.path() / "health.json") << R"({"ok": true, "state": "running", "colour": "blue"})";
  const Expected<std::string> bad = http_reference_page(scratch.path());
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("health.json"), std::string::npos) << bad.error();
  fs::remove(scratch.path() / "pairs.json");
  const Expected<std::string> missing = http_reference_page(scratch.path());
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().find("pairs.json"), std::string::npos) << missing.error();
}

TEST(StatusReferenceTest, HeadingSlugsAreMkDocsAnchorsAndUnique) {
  EXPECT_EQ(heading_slug("Pair episode"), "pair-episode");
  EXPECT_EQ(heading_slug("  Verification and trust "), "verification-and-trust");
  EXPECT_EQ(heading_slug("PromQL examples"), "promql-examples");
  EXPECT_EQ(heading_slug("What's a -- slug?"), "whats-a-slug");
  EXPECT_EQ(heading_slug("poet_env_steps_total"), "poet_env_steps_total");
  const std::string page = generated_http_page();
  std::set<std::string> anchors;
  std::istringstream lines(page);
  for (std::string line; std::getline(lines, line);)
    if (line.starts_with("## ") || line.starts_with("### ")) {
      EXPECT_TRUE(anchors.insert(heading_slug(line.substr(line.find(' ') + 1))).second) << line;
    }
}

}  // namespace
}  // namespace poet
