#include "common/program/tool_flags.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "common/program/build_fingerprint.h"

namespace poet {

WalkerOptions WalkerFlags::options() const {
  return {.push_scale = push_scale, .lidar = lidar == "first" ? LidarRule::kFirst : LidarRule::kNearest};
}

void add_walker_flags(CLI::App& app, WalkerFlags& flags) {
  app.add_option("--push-scale", flags.push_scale, "Initial push F ~ U[-s, s) N (0: none)")
      ->check(CLI::Range(0.0, 1e4));
  app.add_option("--lidar", flags.lidar, "Lidar rule: nearest (default) or first (the reference's)")
      ->check(CLI::IsMember({"nearest", "first"}));
  app.add_option("--max-steps", flags.max_steps, "Time limit in steps")->check(CLI::Range(1, walker::kMaxTimeLimit));
}

int output_checked(const char* tool, int code) {
  errno = 0;
  std::cout.flush();
  const bool failed = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!failed) return code;
  const int error = errno;
  if (error == EPIPE) return code;  // the reader stopped reading (`| head`): what it wanted, it had
  std::fprintf(stderr, "%s: cannot write standard output%s%s\n", tool, error ? ": " : "",
               error ? std::strerror(error) : "");
  return code == 0 ? kExitError : code;
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

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    // app.exit prints help to stdout and errors to stderr; its codes (105, 109, ...) all mean "bad command line"
    return app.exit(e) == 0 ? 0 : kExitUsage;
  }
}

}  // namespace poet
