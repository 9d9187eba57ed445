#include "common/program/tool_flags.h"

#include <iostream>

#include "common/program/build_fingerprint.h"

namespace poet {

WalkerOptions WalkerFlags::options() const {
  return {.push_scale = push_scale, .lidar = lidar == "first" ? LidarRule::kFirst : LidarRule::kNearest};
}

void add_walker_flags(CLI::App& app, WalkerFlags& flags) {
  app.add_option("--push-scale", flags.push_scale, "Initial push F ~ U[-s, s) N (0: none)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e4));
  app.add_option("--lidar", flags.lidar, "Lidar rule: nearest or first (the reference's)")
      ->capture_default_str()
      ->check(CLI::IsMember({"nearest", "first"}));
  app.add_option("--max-steps", flags.max_steps, "Time limit in steps")
      ->capture_default_str()
      ->check(CLI::Range(1, walker::kMaxTimeLimit));
}

void add_fingerprint_flag(CLI::App& app) {
  app.add_flag_callback(
      "--fingerprint",
      [] {
        std::cout << build_fingerprint() << std::flush;
        throw CLI::Success();  // CLI11's way to stop parsing with exit code 0, before required options are checked
      },
      "Print the build's fingerprint (float mode, Box2D version, walker constants) and exit");
}

}  // namespace poet
