#pragma once
// wall_times.csv: how long a run has taken on its machine, for "when was X reached" (poet-report) and where the
// time goes. A header, then one line per saved iteration, "iteration,wall_s,reproduction_s,es_steps_s,
// evaluations_s,transfer_s,waiting_s": the seconds the run's coordinator processes had been running when that
// iteration's checkpoint was written, summed over them (a resume continues the clock from the last line the
// checkpoint has seen), then the seconds each phase of an iteration (poet/phase_observer.h) took since the line
// before, then the seconds of those phases the run loop spent waiting for rollouts (in the evaluator: the rest of
// the wall time is the coordinator's own serial work). Files of earlier builds (headers without waiting_s, or
// "iteration,wall_s" alone) read as before; a resume writes the file again with the full header, its old lines
// keeping their fields. Machine-dependent and outside the run's determinism: nothing in it is read back into the
// state, so a lost or damaged file costs only the times.

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

inline constexpr char kWallTimesFile[] = "wall_times.csv";
inline constexpr char kWallTimesHeader[] =
    "iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s,waiting_s\n";
inline constexpr char kWallTimesHeaderWithoutWaiting[] =
    "iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s\n";
inline constexpr char kWallTimesHeaderWithoutPhases[] = "iteration,wall_s\n";
// A line is a few bytes; this is some ten million iterations.
inline constexpr std::uintmax_t kMaxWallTimesBytes = std::uintmax_t{256} << 20;

// The seconds of each phase, in IterationPhase's order: reproduction, ES steps, evaluations, transfer.
using PhaseSeconds = std::array<double, 4>;
// Their names, as the header's columns (without "_s"), the report's JSON and /metrics' labels have them.
inline constexpr std::array<std::string_view, 4> kPhaseNames = {"reproduction", "es_steps", "evaluations", "transfer"};

struct WallTime {
  int iteration = 0;
  double seconds = 0;
  std::optional<PhaseSeconds> phases;  // nothing on lines of builds that did not time them
  std::optional<double> waiting;       // the same (only with phases)
};

// The lines of a wall_times.csv, in order. Iterations must increase and times must be finite, non-negative and
// not decrease; an error names the line and says what is wrong. With valid_prefix, an error leaves there the lines
// before the first bad one.
Expected<std::vector<WallTime>> parse_wall_times(std::string_view text, std::vector<WallTime>* valid_prefix = nullptr);

// The file's text for these lines (the header, then a line each, as the writer writes them).
std::string wall_times_text(const std::vector<WallTime>& lines);

// Reads a wall_times.csv: its whole lines (a last line without its newline is one being written, or cut by a
// crash, and is left out), parsed. Errors say what is wrong, without the path; valid_prefix as parse_wall_times'.
Expected<std::vector<WallTime>> read_wall_times(const std::filesystem::path& path,
                                                std::vector<WallTime>* valid_prefix = nullptr);

// The writer a coordinator keeps for its run directory.
class WallTimes {
 public:
  // Opens dir/wall_times.csv for a run whose state is at next_iteration: keeps the lines of the iterations before
  // it (later lines timed work the checkpoint did not keep) and rewrites the file atomically. A missing file
  // starts the clock at 0. A damaged one keeps the lines before the damage, and one that cannot be read starts
  // the clock at 0, each with a warning that says why (the state is not affected, only times are lost). A path
  // that cannot be reached (a symbolic-link loop) is left as it is, and nothing is recorded. A last line cut by a
  // crash is dropped. When the file cannot be rewritten, the warning says so and nothing is recorded.
  static WallTimes open(const std::filesystem::path& dir, int next_iteration, std::string* warning);

  // Appends "iteration,carried + seconds,phases...,waiting", seconds being this process's running time, phases the
  // seconds of each phase since the last line and waiting those spent waiting for rollouts. An error names the
  // file. Nothing when open() could not rewrite it.
  std::optional<std::string> record(int iteration, double seconds, const PhaseSeconds& phases, double waiting);

  // The run's time before this process.
  double carried() const { return carried_; }

 private:
  WallTimes(std::filesystem::path path, double carried) : path_(std::move(path)), carried_(carried) {}
  std::filesystem::path path_;
  double carried_ = 0;
};

}  // namespace poet
