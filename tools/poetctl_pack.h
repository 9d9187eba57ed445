#pragma once
// poetctl pack and unpack: a run directory as one file to move between machines (run/run_pack.h), and back.

#include <filesystem>

namespace poet {

// Packs RUN_DIR (its last checkpoint, even while the run goes on) into FILE, verified by reading it back; prints
// what it holds. Returns the exit code: 0, or 1 naming what failed.
int pack_run(const std::filesystem::path& run_dir, const std::filesystem::path& file);

// Restores FILE into DIR (new or empty) without running it; `poet-coordinator --run-dir DIR --resume` goes on.
int unpack_run(const std::filesystem::path& file, const std::filesystem::path& dir);

}  // namespace poet
