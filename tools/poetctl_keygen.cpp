#include "tools/poetctl_keygen.h"

#include <zmq.h>

#include <array>
#include <cstdio>

#include "common/plumbing/curve_keys.h"
#include "common/program/tool_flags.h"
#include "tools/poetctl_exit.h"

namespace poet {

// poetctl keygen: a fresh pair from libzmq's generator, written without replacing any key.
int make_keys(const std::filesystem::path& dir, const std::string& name, bool authorize) {
  if (authorize && name != "worker") {  // before anything is written
    std::fprintf(stderr, "poetctl keygen: --authorize is for worker keys\n");
    return kExitUsage;
  }
  std::array<char, 41> public_key{};
  std::array<char, 41> secret_key{};
  if (zmq_curve_keypair(public_key.data(), secret_key.data()) != 0) {
    std::fprintf(stderr, "poetctl keygen: this libzmq cannot make CURVE keys: %s\n", zmq_strerror(zmq_errno()));
    return kExitUnreachable;
  }
  const CurveKeyPair keys{public_key.data(), secret_key.data()};
  if (auto error = write_key_pair(dir, name, keys)) {
    std::fprintf(stderr, "poetctl keygen: %s\n", error->c_str());
    return kExitUnreachable;
  }
  std::printf("%s/%s.key: %s\n", dir.c_str(), name.c_str(), keys.public_key.c_str());
  if (authorize) {
    const std::filesystem::path authorized = dir / "authorized";
    std::error_code ec;
    std::filesystem::create_directories(authorized, ec);
    std::filesystem::copy_file(dir / (name + ".key"), authorized / (name + ".key"), ec);
    if (ec) {
      std::fprintf(stderr, "poetctl keygen: %s: %s\n", (authorized / (name + ".key")).c_str(), ec.message().c_str());
      return kExitUnreachable;
    }
    std::printf("authorised: %s\n", (authorized / (name + ".key")).c_str());
  }
  return 0;
}

}  // namespace poet
