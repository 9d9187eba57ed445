#pragma once
// Held-out test suites: named, fixed sets of courses that no run trains on, by which a policy's generalisation is
// judged. A suite has one group per difficulty level (spec §1.4), each of `encodings` courses drawn at that level
// as the paper draws its coverage sample and each course run on `seeds` fixed terrain seeds, and a group on the
// hardcore-like course (Gym's BipedalWalkerHardcore ranges, stairs included). A suite never changes once named: a
// changed definition gets a new name (tests pin each suite's contents).

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "simulation/envgen/env_encoding.h"
#include "simulation/rollout.h"

namespace poet {

struct SuiteCourse {
  EnvEncoding encoding;         // named <group>-<index>, e.g. "challenging-07"
  std::vector<uint32_t> seeds;  // its terrain seeds, in the order they are run
};

struct SuiteGroup {
  std::string name;  // "easy", "challenging", "very challenging", "extremely challenging", "hardcore-like"
  std::vector<SuiteCourse> courses;
  int episodes() const;
};

struct CourseSuite {
  std::string name;
  std::vector<SuiteGroup> groups;
  int episodes() const;
};

// The suites this build knows, by name ("poet-suite-v1", ...); nullopt for an unknown name.
std::optional<CourseSuite> named_suite(std::string_view name);
std::span<const std::string_view> suite_names();

// A suite built the way every named suite is: `encodings` courses per level, each on `seeds` terrain seeds, and
// encodings × seeds episodes of the hardcore-like course, all drawn from `seed`. Requires both counts ≥ 1.
CourseSuite make_suite(std::string name, uint64_t seed, int encodings, int seeds);

// One group's episodes, course by course and seed by seed in the suite's order.
struct GroupScore {
  std::string group;
  std::vector<RolloutResult> episodes;

  int finished() const;
  double finished_fraction() const;
  // The Wilson score interval (95%) of the fraction finished: the range that holds the policy's true rate on
  // courses drawn like these, given n episodes.
  std::pair<double, double> finished_interval() const;
  double mean_return() const;
  // How far along the course the walkers got, from the start (0) to the finish line (1), on average: the measure
  // that tells a walker that went halfway and fell from one that stood still, which the return does not (a fall
  // costs 100, so standing scores higher than falling halfway).
  double mean_progress() const;
  double return_sd() const;               // sample standard deviation (0 for one episode)
  double mean_return_half_width() const;  // 1.96 sd / √n: the 95% interval of the mean is mean ± this
};

struct SuiteScore {
  std::string suite;
  std::vector<GroupScore> groups;  // in the suite's order
  int episodes() const;
  int finished() const;
  double finished_fraction() const;  // over every episode of the suite
  double mean_return() const;        // over every episode of the suite
  double mean_progress() const;      // over every episode of the suite
};

// An episode's progress: its hull's x from the start to the finish line as a fraction, clamped to [0, 1].
double progress(const RolloutResult& episode);

// The policy's episodes on every course of the suite on up to `threads` threads; the result does not depend on
// `threads`.
SuiteScore run_suite(const Mlp& policy, const CourseSuite& suite, const WalkerOptions& options = {},
                     int max_steps = walker::kDefaultTimeLimit, int threads = 1);

}  // namespace poet
