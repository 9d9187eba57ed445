// poet-rollout: one episode of a policy on one course. Prints the policy it runs, the walk (hull position every few
// steps), the return, the steps and the outcome, and draws the course with the walker's path (and, with --gif, the
// walker crossing it).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "common/formats/envgen/env_json.h"
#include "common/formats/policy/policy_file.h"
#include "common/program/tool_flags.h"
#include "pictures/course_picture.h"
#include "pictures/walker_pictures.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "simulation/rollout.h"

namespace {

std::string outcome(const poet::RolloutResult& r) {
  if (r.finished && r.fell) return "finished (and fell on the last step)";
  if (r.finished) return "finished";
  if (r.fell) return "fell";
  return "timed out";
}

}  // namespace

int run_tool(int argc, char** argv) {
  CLI::App app{"Run one walker episode and draw it"};
  std::string policy_path, env_path, course = "flat", picture = "rollout.svg";
  std::optional<uint64_t> random_seed;
  std::optional<uint32_t> seed;
  poet::WalkerFlags walker;
  int print_every = 100;
  auto* policy_opt = app.add_option("--policy", policy_path,
                                    "Policy file, JSON [[p0..p2803], score] (default: none, random parameters)");
  app.add_option(
         "--random", random_seed,
         "Use random initial parameters θ ~ N(0, 0.1²) drawn with this seed (default: 0 when --policy is not given)")
      ->excludes(policy_opt);
  auto* env_opt = app.add_option(
      "--env", env_path, "Environment definition, JSON {\"config\": ..., \"seed\": s} (default: none, --course)");
  app.add_option("--course", course, "Named course: flat, r1, r3, hard, hardcore-like")
      ->capture_default_str()
      ->excludes(env_opt);
  app.add_option("--seed", seed, "Terrain seed, overriding the env file's (default: the env file's, or 0 for a course)")
      ->check(CLI::Range(0u, 999999u));
  poet::add_walker_flags(app, walker);
  app.add_option("--print-every", print_every, "Print the walker's position every N steps (0: never)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1'000'000));
  app.add_option("--picture", picture, "Picture to write: .svg or .png (empty: none)")->capture_default_str();
  std::string gif;
  app.add_option("--gif", gif, "Also write the walker crossing its course as an animated GIF here (default: none)");
  poet::add_fingerprint_flag(app);
  if (auto code = poet::parse_command_line(app, argc, argv)) return *code;

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

  // the policy, named on stdout so that a walk is never taken for a trained walker's by mistake
  std::vector<double> params;
  if (!policy_path.empty()) {
    auto loaded = poet::load_policy(policy_path);
    if (!loaded) {
      std::fprintf(stderr, "poet-rollout: %s\n", loaded.error().c_str());
      return 2;
    }
    params = loaded->params;
    std::printf("policy: %s\n", policy_path.c_str());
  } else {
    const uint64_t draw_seed = random_seed.value_or(0);
    poet::RandomStream rng(poet::stream_key(draw_seed, "init"));
    params = poet::random_params(rng);
    std::printf("policy: random θ ~ N(0, 0.1²) drawn with seed %llu (%s)\n", static_cast<unsigned long long>(draw_seed),
                random_seed ? "--random" : "no --policy given");
  }

  const poet::Terrain terrain = poet::Terrain::generate(env);
  const poet::RolloutResult r = poet::rollout(poet::Mlp(params), terrain, walker.options(),
                                              {.max_steps = walker.max_steps, .record_trajectory = true});

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
  if (!gif.empty()) {
    const poet::Expected<std::string> bytes = poet::render_walk_gif(terrain, r);
    const std::string err = bytes ? poet::write_bytes(gif, *bytes) : "cannot draw " + gif + ": " + bytes.error();
    if (!err.empty()) {
      std::fprintf(stderr, "poet-rollout: %s\n", err.c_str());
      return 1;
    }
    std::printf("gif: %s\n", gif.c_str());
  }
  return 0;
}

int main(int argc, char** argv) { return poet::output_checked("poet-rollout", run_tool(argc, argv)); }
