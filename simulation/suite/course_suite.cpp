#include "simulation/suite/course_suite.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <stdexcept>

#include "simulation/envgen/level_sample.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/parallel_for.h"
#include "simulation/rng.h"
#include "simulation/walker/terrain.h"
#include "simulation/walker/walker_constants.h"

namespace poet {
namespace {

// Every named suite: its name, the seed its courses are drawn from, encodings per level and seeds per encoding.
struct SuiteRecipe {
  std::string_view name;
  uint64_t seed;
  int encodings;
  int seeds;
};
// poet-suite-v1: 50 encodings per level on 2 terrain seeds each, 100 episodes per group, 500 in all. More
// encodings than seeds, because courses of one encoding are alike: what varies most is the encoding.
constexpr std::array kSuites = {SuiteRecipe{"poet-suite-v1", 20261126, 50, 2}};
constexpr auto kSuiteNames = [] {
  std::array<std::string_view, kSuites.size()> names{};
  for (size_t i = 0; i < kSuites.size(); ++i) names[i] = kSuites[i].name;
  return names;
}();

constexpr double kZ95 = 1.959963984540054;

std::vector<uint32_t> draw_seeds(RandomStream& stream, int count) {
  std::vector<uint32_t> seeds;
  for (int i = 0; i < count; ++i) seeds.push_back(static_cast<uint32_t>(stream.uniform_int(0, kMaxEnvSeed)));
  return seeds;
}

std::string course_label(std::string_view group, int index) {
  char number[16];
  std::snprintf(number, sizeof number, "-%02d", index);
  std::string label(group);
  for (char& c : label)
    if (c == ' ') c = '-';
  return label + number;
}

}  // namespace

int SuiteGroup::episodes() const {
  int n = 0;
  for (const SuiteCourse& c : courses) n += static_cast<int>(c.seeds.size());
  return n;
}

int CourseSuite::episodes() const {
  int n = 0;
  for (const SuiteGroup& g : groups) n += g.episodes();
  return n;
}

CourseSuite make_suite(std::string name, uint64_t seed, int encodings, int seeds) {
  if (encodings < 1 || seeds < 1) throw std::invalid_argument("a suite needs at least one encoding and one seed");
  CourseSuite suite{std::move(name), {}};
  for (int level = 0; level <= 3; ++level) {
    const auto difficulty_level = static_cast<Difficulty>(level);
    SuiteGroup group{std::string(to_string(difficulty_level)), {}};
    RandomStream courses(stream_key(seed, "suite courses", {static_cast<uint64_t>(level)}));
    RandomStream terrain(stream_key(seed, "suite seeds", {static_cast<uint64_t>(level)}));
    for (int k = 0; k < encodings; ++k)
      group.courses.push_back({course_of(draw_env_vector(courses, difficulty_level), course_label(group.name, k)),
                               draw_seeds(terrain, seeds)});
    suite.groups.push_back(std::move(group));
  }
  RandomStream terrain(stream_key(seed, "suite seeds", {4}));
  SuiteGroup hardcore{"hardcore-like", {{*named_course("hardcore-like"), draw_seeds(terrain, encodings * seeds)}}};
  suite.groups.push_back(std::move(hardcore));
  return suite;
}

std::optional<CourseSuite> named_suite(std::string_view name) {
  for (const SuiteRecipe& r : kSuites)
    if (r.name == name) return make_suite(std::string(name), r.seed, r.encodings, r.seeds);
  return std::nullopt;
}

std::span<const std::string_view> suite_names() { return kSuiteNames; }

int GroupScore::finished() const {
  int n = 0;
  for (const RolloutResult& e : episodes) n += e.finished ? 1 : 0;
  return n;
}

double GroupScore::finished_fraction() const {
  return episodes.empty() ? 0.0 : static_cast<double>(finished()) / static_cast<double>(episodes.size());
}

std::pair<double, double> GroupScore::finished_interval() const {
  if (episodes.empty()) return {0.0, 1.0};
  const double n = static_cast<double>(episodes.size());
  const double p = finished_fraction();
  const double z2 = kZ95 * kZ95;
  const double centre = (p + z2 / (2 * n)) / (1 + z2 / n);
  const double half = kZ95 / (1 + z2 / n) * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n));
  // the ends are exact: none finished puts the low end at 0, all at the high end at 1 (rounding would miss them)
  const int k = finished();
  return {k == 0 ? 0.0 : std::max(0.0, centre - half),
          k == static_cast<int>(episodes.size()) ? 1.0 : std::min(1.0, centre + half)};
}

double GroupScore::mean_return() const {
  if (episodes.empty()) return 0.0;
  double sum = 0;
  for (const RolloutResult& e : episodes) sum += e.total_reward;
  return sum / static_cast<double>(episodes.size());
}

double progress(const RolloutResult& episode) {
  const double x = (episode.final_x - walker::kInitX) / (walker::kFinishX - walker::kInitX);
  return std::clamp(x, 0.0, 1.0);
}

double GroupScore::mean_progress() const {
  if (episodes.empty()) return 0.0;
  double sum = 0;
  for (const RolloutResult& e : episodes) sum += progress(e);
  return sum / static_cast<double>(episodes.size());
}

double GroupScore::return_sd() const {
  if (episodes.size() < 2) return 0.0;
  const double mean = mean_return();
  double squares = 0;
  for (const RolloutResult& e : episodes) squares += (e.total_reward - mean) * (e.total_reward - mean);
  return std::sqrt(squares / static_cast<double>(episodes.size() - 1));
}

double GroupScore::mean_return_half_width() const {
  return episodes.empty() ? 0.0 : kZ95 * return_sd() / std::sqrt(static_cast<double>(episodes.size()));
}

int SuiteScore::episodes() const {
  int n = 0;
  for (const GroupScore& g : groups) n += static_cast<int>(g.episodes.size());
  return n;
}

int SuiteScore::finished() const {
  int n = 0;
  for (const GroupScore& g : groups) n += g.finished();
  return n;
}

double SuiteScore::finished_fraction() const {
  return episodes() == 0 ? 0.0 : static_cast<double>(finished()) / static_cast<double>(episodes());
}

double SuiteScore::mean_return() const {
  double sum = 0;
  for (const GroupScore& g : groups) sum += g.mean_return() * static_cast<double>(g.episodes.size());
  return episodes() == 0 ? 0.0 : sum / static_cast<double>(episodes());
}

double SuiteScore::mean_progress() const {
  double sum = 0;
  for (const GroupScore& g : groups) sum += g.mean_progress() * static_cast<double>(g.episodes.size());
  return episodes() == 0 ? 0.0 : sum / static_cast<double>(episodes());
}

SuiteScore run_suite(const Mlp& policy, const CourseSuite& suite, const WalkerOptions& options, int max_steps,
                     int threads) {
  // every episode of the suite in one list, so that threads stay busy across courses and groups
  struct Episode {
    const EnvEncoding* encoding;
    uint32_t seed;
    size_t group;
  };
  std::vector<Episode> list;
  for (size_t g = 0; g < suite.groups.size(); ++g)
    for (const SuiteCourse& c : suite.groups[g].courses)
      for (uint32_t seed : c.seeds) list.push_back({&c.encoding, seed, g});
  std::vector<RolloutResult> results(list.size());
  parallel_for(static_cast<int>(list.size()), threads, [&](int i) {
    const Episode& e = list[static_cast<size_t>(i)];
    results[static_cast<size_t>(i)] =
        rollout(policy, Terrain::generate({*e.encoding, e.seed}), options, {.max_steps = max_steps});
  });
  SuiteScore score{suite.name, {}};
  for (const SuiteGroup& g : suite.groups) score.groups.push_back({g.name, {}});
  for (size_t i = 0; i < list.size(); ++i) score.groups[list[i].group].episodes.push_back(std::move(results[i]));
  return score;
}

}  // namespace poet
