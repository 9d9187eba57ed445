#include "tools/poetctl_pack.h"

#include <cstdio>
#include <string>

#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_pack.h"
#include "tools/poetctl_exit.h"

namespace poet {
namespace {

void print_contents(const PackSummary& pack) {
  for (const PackEntry& e : pack.entries) std::printf("  %-16s %12zu bytes\n", e.name.c_str(), e.content.size());
}

}  // namespace

int pack_run(const std::filesystem::path& run_dir, const std::filesystem::path& file) {
  const Expected<PackSummary> pack = write_run_pack(run_dir, file);
  if (!pack) {
    std::fprintf(stderr, "poetctl pack: %s\n", pack.error().c_str());
    return kExitUnreachable;
  }
  std::printf("packed %s at iteration %d into %s (%llu bytes, read back and verified):\n", run_dir.c_str(),
              pack->next_iteration, file.c_str(), static_cast<unsigned long long>(pack->pack_bytes));
  print_contents(*pack);
  std::printf("go on elsewhere with: poet-coordinator --run-dir DIR --resume --from-pack %s\n",
              file.filename().c_str());
  return 0;
}

int unpack_run(const std::filesystem::path& file, const std::filesystem::path& dir) {
  const Expected<PackSummary> pack = restore_run_pack(file, dir, OpenFor::kReading);
  if (!pack) {
    std::fprintf(stderr, "poetctl unpack: %s\n", pack.error().c_str());
    return kExitUnreachable;
  }
  // opened once as a resume opens it: the files derived from the checkpoint (config.textproto, annecs.csv, envs/,
  // policies/) are written, so that tools reading a run directory find it whole
  if (const auto opened = RunDirectory::resume(dir, OpenFor::kReading); !opened) {
    std::fprintf(stderr, "poetctl unpack: %s\n", opened.error().c_str());
    return kExitUnreachable;
  }
  std::printf("restored %s into %s at iteration %d (with the files derived from its checkpoint):\n", file.c_str(),
              dir.c_str(), pack->next_iteration);
  print_contents(*pack);
  if (pack->unknown_fields) {
    std::printf("to read only: %s\n", pack->unknown_fields->c_str());
    return 0;
  }
  if (const std::optional<std::string> refusal = arithmetic_refusal(pack->arithmetic_digest)) {
    std::printf("to read only: %s\n", refusal->c_str());
    return 0;
  }
  std::printf("go on with: poet-coordinator --run-dir %s --resume\n", dir.c_str());
  return 0;
}

}  // namespace poet
