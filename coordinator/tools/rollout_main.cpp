// poet-rollout: one episode of a policy on one course. Prints the walk (hull position every few steps), the
// return, the steps and the outcome, and draws the course with the walker's path.

#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "course_picture.h"
#include "envgen/env_json.h"
#include "envgen/named_courses.h"
#include "policy/mlp.h"
#include "policy/policy_file.h"
#include "rng.h"
#include "rollout.h"

namespace {

std::string outcome(const poet::RolloutResult& r) {
  if (r.finished && r.fell) return "finished (and fell on the last step)";
  if (r.finished) return "finished";
  if (r.fell) return "fell";
  return "timed out";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Run one walker episode and draw it"};
  std::string policy_path, env_path, course = "flat", picture = "rollout.svg", lidar = "nearest";
  std::optional<uint64_t> random_seed;
  std::optional<uint32_t> seed;
  double push_scale = poet::walker::kDefaultPushScale;
  int max_steps = poet::walker::kDefaultTimeLimit, print_every = 100;
  auto* policy_opt = app.add_option("--policy", policy_path, "Policy file, JSON [[p0..p2803], score]");
  app.add_option("--random", random_seed, "Use random initial parameters θ ~ N(0, 0.1²) drawn with this seed")
      ->excludes(policy_opt);
  auto* env_opt = app.add_option("--env", env_path, "Environment definition, JSON {\"config\": ..., \"seed\": s}");
  app.add_option("--course", course, "Named course: flat, r1, r3, hard, hardcore-like")->excludes(env_opt);
  app.add_option("--seed", seed, "Terrain seed (overrides the env file's)")->check(CLI::Range(0u, 999999u));
  app.add_option("--push-scale", push_scale, "Initial push F ~ U[-s, s) N (0: none)")->check(CLI::Range(0.0, 1e4));
  app.add_option("--lidar", lidar, "Lidar rule: nearest (default) or first (the reference's)")
      ->check(CLI::IsMember({"nearest", "first"}));
  app.add_option("--max-steps", max_steps, "Time limit in steps")->check(CLI::Range(1, 1'000'000));
  app.add_option("--print-every", print_every, "Print the walker's position every N steps (0: never)")
      ->check(CLI::Range(0, 1'000'000));
  app.add_option("--picture", picture, "Picture to write: .svg or .png (empty: none)");
  CLI11_PARSE(app, argc, argv);

  // the course
  poet::EnvDef env;
  if (!env_path.empty()) {
    auto loaded = poet::load_env_def(env_path);
    if (!loaded) {
      std::fprintf(stderr, "poet-rollout: %s\n", loaded.error().c_str());
      return 2;
    }
    env = *loaded;
  } else {
    auto encoding = poet::named_course(course);
    if (!encoding) {
      std::fprintf(stderr, "poet-rollout: unknown course '%s'\n", course.c_str());
      return 2;
    }
    env.encoding = *encoding;
  }
  if (seed) env.seed = *seed;

  // the policy
  std::vector<double> params;
  if (!policy_path.empty()) {
    auto loaded = poet::load_policy(policy_path);
    if (!loaded) {
      std::fprintf(stderr, "poet-rollout: %s\n", loaded.error().c_str());
      return 2;
    }
    params = loaded->params;
  } else {
    poet::RandomStream rng(poet::stream_key(random_seed.value_or(0), "init"));
    params = poet::random_params(rng);
  }

  const poet::Terrain terrain = poet::Terrain::generate(env);
  const poet::WalkerOptions options{push_scale, lidar == "first" ? poet::LidarRule::kFirst : poet::LidarRule::kNearest};
  const poet::RolloutResult r =
      poet::rollout(poet::Mlp(params), terrain, options, {.max_steps = max_steps, .record_trajectory = true});

  std::printf("course %s, seed %u: %zu obstacles\n", poet::reference_name(env.encoding).c_str(), env.seed,
              terrain.features().size());
  if (print_every > 0) {
    std::printf("%8s %9s %9s %9s\n", "step", "hull x", "hull y", "angle");
    for (size_t k = 0; k < r.trajectory.size(); k += static_cast<size_t>(print_every)) {
      const auto& hull = r.trajectory[k][0];
      std::printf("%8zu %9.3f %9.3f %9.3f\n", k, hull.x, hull.y, hull.angle);
    }
  }
  std::printf("return %.3f over %d steps: %s (hull at x = %.2f m of %.2f)\n", r.total_reward, r.steps,
              outcome(r).c_str(), r.final_x, poet::walker::kFinishX);
  if (!picture.empty()) {
    if (std::string err = poet::write_course_picture(picture, terrain, r); !err.empty()) {
      std::fprintf(stderr, "poet-rollout: %s\n", err.c_str());
      return 1;
    }
    std::printf("picture: %s\n", picture.c_str());
  }
  return 0;
}
