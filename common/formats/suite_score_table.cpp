#include "common/formats/suite_score_table.h"

#include <cstdio>

namespace poet {
namespace {

std::string line(const char* format, auto... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, format, args...);
  return buffer;
}

// "very challenging" → "very", "extremely challenging" → "extremely": a column heading.
std::string short_name(const std::string& group) { return group.substr(0, group.find(' ')); }

}  // namespace

std::string suite_table(const SuiteScore& score) {
  std::string out = line("suite %s: %d episodes, %d finished (%.1f%%), mean return %.2f, mean progress %.1f%%\n",
                         score.suite.c_str(), score.episodes(), score.finished(), 100 * score.finished_fraction(),
                         score.mean_return(), 100 * score.mean_progress());
  out += line("%-22s %8s %8s %9s %18s %12s %10s %9s %9s\n", "group", "episodes", "finished", "fraction", "95% interval",
              "mean return", "± (95%)", "sd", "progress");
  for (const GroupScore& g : score.groups) {
    const auto [lo, hi] = g.finished_interval();
    out += line("%-22s %8zu %8d %8.1f%% %8.1f%%–%5.1f%% %12.2f %10.2f %9.2f %8.1f%%\n", g.group.c_str(),
                g.episodes.size(), g.finished(), 100 * g.finished_fraction(), 100 * lo, 100 * hi, g.mean_return(),
                g.mean_return_half_width(), g.return_sd(), 100 * g.mean_progress());
  }
  return out;
}

std::string suite_rows_header(const SuiteScore& any) {
  std::string out = line("%-24s", "policy");
  for (const GroupScore& g : any.groups) out += line(" %13s", short_name(g.group).c_str());
  return out + line(" %13s %9s %12s\n", "all", "progress", "mean return");
}

std::string suite_row(const std::string& label, const SuiteScore& score) {
  std::string out = line("%-24.24s", label.c_str());
  for (const GroupScore& g : score.groups) out += line(" %6d of %-3zu", g.finished(), g.episodes.size());
  return out + line(" %6d of %-3d %8.1f%% %12.2f\n", score.finished(), score.episodes(), 100 * score.mean_progress(),
                    score.mean_return());
}

}  // namespace poet
