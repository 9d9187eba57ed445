// poet-fidelity: the side-by-side table of docs/fidelity.md — the reference walker's figures next to this
// project's, every one computed here by the same code the alignment tests use. Reference figures come from the
// trace files in --reference when present; the sweep and statistics figures of the reference are quoted from its
// documents (estool-zoo/README.md, STATISTICS.md).

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "common/formats/policy/policy_file.h"
#include "common/program/tool_flags.h"
#include "simulation/course_statistics.h"
#include "simulation/course_sweep.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/rng.h"
#include "simulation/rollout.h"

namespace {

using namespace poet;
namespace fs = std::filesystem;

const WalkerOptions kNoPush{.push_scale = 0};
int g_threads = 2;

void row(const std::string& what, const std::string& reference, const std::string& project) {
  std::printf("| %s | %s | %s |\n", what.c_str(), reference.c_str(), project.c_str());
}

std::string fmt(const char* f, double a) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, a);
  return buf;
}

std::string sweep_cell(const CourseSweep& s) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%.1f (%.1f) %d/50, %d fell, %.0f", s.mean_return(), s.min_return(), s.finished(),
                s.fell(), s.mean_steps());
  return buf;
}

// The reference's trace files are a few hundred kilobytes; a larger one is not one of them.
constexpr std::uintmax_t kMaxTraceBytes = 64u << 20;

// Reads a trace file and hands it to `read`; whatever is missing or of the wrong type in it (read uses at(), which
// throws, never operator[] on a const json, which does not check) comes back as an error naming the file.
template <typename Read>
void read_trace(const fs::path& file, Read&& read) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw std::runtime_error(file.string() + ": not a file");
  if (fs::file_size(file, ec) > kMaxTraceBytes) throw std::runtime_error(file.string() + ": larger than 64 MB");
  try {
    std::ifstream in(file);
    read(nlohmann::json::parse(in));
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
}

void traces(const fs::path& ref) {
  std::printf(
      "\n### Traces: flat course, push 0 (walker-traces/)\n\n| figure | reference | this project |\n|---|---|---|\n");
  const Terrain flat = Terrain::generate({*named_course("flat"), 0});
  read_trace(ref / "walker-traces/T1_zero_action.json", [&](const nlohmann::json& t1) {
    WalkerEnv env(flat, kNoPush);
    const Observation obs = env.reset();
    double worst_mass = 0, worst_angle = 0, worst_obs = 0;
    const auto bodies = env.body_setup();
    const auto joints = env.joint_setup();
    const nlohmann::json& setup = t1.at("setup");
    for (size_t i = 0; i < bodies.size(); ++i)
      worst_mass = std::max(worst_mass, std::abs(bodies[i].mass - setup.at("bodies").at(i).at("mass").get<double>()));
    for (size_t j = 0; j < joints.size(); ++j)
      worst_angle = std::max(worst_angle, std::abs(joints[j].reference_angle -
                                                   setup.at("joints").at(j).at("reference_angle").get<double>()));
    for (size_t i = 0; i < obs.size(); ++i)
      worst_obs = std::max(worst_obs, std::abs(obs[i] - t1.at("reset").at("obs").at(i).get<double>()));
    row("body masses (5 bodies), largest difference", "T1 setup", fmt("%.1e kg", worst_mass));
    row("joint reference angles, largest difference", "−0.05, 0, +0.05, 0", fmt("%.1e rad", worst_angle));
    row("reset observation, largest element difference", "T1 reset.obs", fmt("%.1e", worst_obs));
    const RolloutResult zero = rollout(Mlp(zero_params()), flat, kNoPush);
    const nlohmann::json& summary = t1.at("summary");
    row("T1 zero action: steps, return",
        std::to_string(summary.at("n_steps").get<int>()) + ", " + fmt("%.2f", summary.at("total_return").get<double>()),
        std::to_string(zero.steps) + ", " + fmt("%.2f", zero.total_reward));
  });

  read_trace(ref / "walker-traces/T2_scripted_actions.json", [&](const nlohmann::json& t2) {
    WalkerEnv scripted(flat, kNoPush);
    scripted.reset();
    const nlohmann::json& first = t2.at("steps").at(0);
    const nlohmann::json& a = first.at("action");
    scripted.step({a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>(), a.at(3).get<double>()});
    row("T2 step 1: leg 1 knee angle (limit −0.1)", fmt("%+.3f rad", first.at("joint_angle").at(1).get<double>()),
        fmt("%+.3f rad", scripted.observation()[6] - 1.0));
  });

  read_trace(ref / "walker-traces/T3_trained_policies.json", [&](const nlohmann::json& t3) {
    for (const auto& p : t3.at("policies")) {
      const std::string file = p.at("policy_file").get<std::string>();
      auto policy = load_policy(ref / file);
      if (!policy) throw std::runtime_error(policy.error());
      const RolloutResult r = rollout(Mlp(policy->params), flat, kNoPush);
      row("T3 " + fs::path(file).stem().string() + ": return, steps, finished",
          fmt("%.2f", p.at("total_return").get<double>()) + ", " + std::to_string(p.at("n_steps").get<int>()) +
              (p.at("finished").get<bool>() ? ", yes" : ", no"),
          fmt("%.2f", r.total_reward) + ", " + std::to_string(r.steps) + (r.finished ? ", yes" : ", no"));
    }
  });
}

void trained_walkers(const fs::path& ref) {
  std::printf(
      "\n### Trained walkers, terrain seeds 0…49: mean (min) finished/50, fell, mean steps\n\n"
      "| walker, course | reference (estool-zoo/README.md) | this project |\n|---|---|---|\n");
  struct Cell {
    const char* policy;
    const char* course;
    const char* reference;
  };
  const Cell cells[] = {
      {"biped.cma.1.96.best", "flat", "315.3 (310.9) 50/50, 0 fell, 1368"},
      {"biped.cma.1.96.best", "r1", "314.6 (307.4) 50/50, 0 fell, 1389"},
      {"biped.cma.1.96.best", "r3", "−7.6 (−79.1) 0/50, 48 fell, 681"},
      {"biped.cma.1.96.best", "hardcore-like", "−60.2 (−125.2) 0/50, 37 fell, 786"},
      {"bipedhard.256.16.v4", "flat", "325.8 (324.6) 50/50, 0 fell, 1113"},
      {"bipedhard.256.16.v4", "r1", "325.3 (323.8) 50/50, 0 fell, 1095"},
      {"bipedhard.256.16.v4", "r3", "317.9 (171.2) 49/50, 0 fell, 1183"},
      {"bipedhard.256.16.v4", "hardcore-like", "291.4 (−22.7) 47/50, 3 fell, 1320"},
      {"more/bipedhard/bipedhard.2", "flat", "324.3 (323.5) 50/50, 0 fell, 1341"},
      {"more/bipedhard/bipedhard.2", "r1", "324.0 (322.3) 50/50, 0 fell, 1337"},
      {"more/bipedhard/bipedhard.2", "r3", "302.0 (−27.4) 46/50, 4 fell, 1282"},
      {"more/bipedhard/bipedhard.2", "hardcore-like", "290.8 (−74.1) 46/50, 4 fell, 1253"},
  };
  for (const Cell& c : cells) {
    auto policy = load_policy(ref / "estool-zoo/zoo" / (std::string(c.policy) + ".json"));
    if (!policy) throw std::runtime_error(policy.error());
    const CourseSweep s = sweep_course(Mlp(policy->params), c.course, *named_course(c.course), 0, 50, {},
                                       walker::kDefaultTimeLimit, g_threads);
    row(std::string(c.policy) + ", " + c.course, c.reference, sweep_cell(s));
  }
  // the deliberate lidar difference on a trained walker (trained with first-hit lidar)
  auto hard2 = load_policy(ref / "estool-zoo/zoo/more/bipedhard/bipedhard.2.json");
  for (const auto& [label, first, count] : {std::tuple{"0…49", 0u, 50}, std::tuple{"0…199", 0u, 200}}) {
    for (LidarRule rule : {LidarRule::kNearest, LidarRule::kFirst}) {
      const CourseSweep s = sweep_course(Mlp(hard2->params), "hardcore-like", *named_course("hardcore-like"), first,
                                         count, {.lidar = rule}, walker::kDefaultTimeLimit, g_threads);
      row(std::string("bipedhard.2, hardcore-like, seeds ") + label + ", " +
              (rule == LidarRule::kFirst ? "first-hit" : "nearest") + " lidar",
          "—",
          fmt("mean %.1f, ", s.mean_return()) + std::to_string(s.finished()) + "/" + std::to_string(count) +
              " finished");
    }
  }
}

void statistics() {
  std::printf(
      "\n### Courses and random initial policies, terrain seeds 0…49\n\n"
      "| figure | reference (STATISTICS.md) | this project |\n|---|---|---|\n");
  for (double r : {1.0, 3.0}) {
    EnvEncoding e;
    e.roughness = r;
    row(fmt("mean |Δy|, roughness %.0f (m)", r), fmt("%.4f", 0.02045 * r),
        fmt("%.4f", terrain_statistics(e, 0, 50).mean_abs_dy));
  }
  const TerrainStatistics hard = terrain_statistics(*named_course("hard"), 0, 50);
  const TerrainStatistics like = terrain_statistics(*named_course("hardcore-like"), 0, 50);
  row("hard: obstacles per course (pits, stumps)", "17.16 (9.04, 8.12)",
      fmt("%.2f", hard.obstacles) + fmt(" (%.2f, ", hard.pits) + fmt("%.2f)", hard.stumps));
  row("hard: mean pit width, stump height (steps)", "3.991, 2.010",
      fmt("%.3f, ", hard.mean_pit_width) + fmt("%.3f", hard.mean_stump_height));
  row("hardcore-like: obstacles per course (pits, stumps, stairs)", "13.16 (4.76, 4.20, 4.20)",
      fmt("%.2f", like.obstacles) + fmt(" (%.2f, ", like.pits) + fmt("%.2f, ", like.stumps) +
          fmt("%.2f)", like.stairs));
  row("hardcore-like: mean pit width, stump height (steps)", "3.048, 1.229",
      fmt("%.3f, ", like.mean_pit_width) + fmt("%.3f", like.mean_stump_height));
  struct Ref {
    const char* course;
    const char* figures;
  };
  for (const Ref& r : {Ref{"flat", "−94.0, 0.645, 127"}, Ref{"r1", "−94.0, 0.645, 128"}, Ref{"r3", "−94.0, 0.650, 128"},
                       Ref{"hard", "−94.0, 0.635, 130"}, Ref{"hardcore-like", "−94.0, 0.640, 126"}}) {
    const RandomPolicyStatistics s = random_policy_statistics(*named_course(r.course), 200, 1, {}, g_threads);
    row(std::string("200 random policies on ") + r.course + ": median return, fell, median steps", r.figures,
        fmt("%.1f, ", s.median_return) + fmt("%.3f, ", s.fell) + fmt("%.1f", s.median_steps));
  }
}

// How often the two lidar rules read differently, over the steps of random-action episodes.
void lidar_rules() {
  std::printf(
      "\n### Lidar rule: rays that read differently, first-hit vs nearest\n\n"
      "| course | rays differing (random-action episodes, 20 seeds) |\n|---|---|\n");
  for (const char* course : {"r1", "r3", "hard", "hardcore-like"}) {
    long differ = 0, total = 0;
    for (uint32_t seed = 0; seed < 20; ++seed) {
      const Terrain t = Terrain::generate({*named_course(course), seed});
      WalkerEnv nearest(t, {.lidar = LidarRule::kNearest}), first(t, {.lidar = LidarRule::kFirst});
      nearest.reset();
      first.reset();
      RandomStream rng(stream_key(seed, "fidelity-actions"));
      for (int k = 0; k < 400; ++k) {
        const Action a = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
        const bool done = nearest.step(a).done();
        first.step(a);  // same physics: observing does not change the world
        for (int i = 14; i < 24; ++i) differ += nearest.observation()[i] != first.observation()[i];
        total += 10;
        if (done) break;
      }
    }
    std::printf("| %s | %.1f %% |\n", course, 100.0 * double(differ) / double(total));
  }
}

}  // namespace

int run_tool(int argc, char** argv) {
  CLI::App app{"Print the fidelity table: the reference walker's figures next to this project's"};
  std::string reference = POET_REFERENCE_DIR;
  g_threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--reference", reference,
                 "Directory of the reference data, walker-traces/ and estool-zoo/ (default: POET_REFERENCE_DIR of the "
                 "build's configure)");
  app.add_option("--threads", g_threads, "Worker threads (default: hardware concurrency)")->check(CLI::Range(1, 256));
  add_fingerprint_flag(app);
  if (auto code = parse_command_line(app, argc, argv)) return *code;

  std::printf("## Fidelity table (generated by poet-fidelity)\n");
  try {
    if (reference.empty()) {
      std::printf("\nNo reference data given (--reference DIR): trace and trained-walker rows skipped.\n");
    } else if (fs::exists(fs::path(reference) / "walker-traces")) {
      traces(reference);
      trained_walkers(reference);
    } else {
      std::printf("\nReference data not found at %s: trace and trained-walker rows skipped.\n", reference.c_str());
    }
    statistics();
    lidar_rules();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "poet-fidelity: %s\n", e.what());
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) { return poet::output_checked("poet-fidelity", run_tool(argc, argv)); }
