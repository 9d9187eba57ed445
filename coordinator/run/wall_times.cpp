#include "run/wall_times.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <system_error>

#include "text_file.h"

namespace poet {
namespace {

std::string line_text(int iteration, double seconds) {
  char buffer[64];
  const int n = std::snprintf(buffer, sizeof buffer, "%d,%.3f\n", iteration, seconds);
  return std::string(buffer, static_cast<size_t>(n));
}

}  // namespace

std::string wall_times_text(const std::vector<WallTime>& lines) {
  std::string text = kWallTimesHeader;
  for (const WallTime& w : lines) text += line_text(w.iteration, w.seconds);
  return text;
}

Expected<std::vector<WallTime>> parse_wall_times(std::string_view text) {
  std::vector<WallTime> out;
  size_t line_number = 0;
  while (!text.empty()) {
    const size_t end = text.find('\n');
    if (end == std::string_view::npos) return Unexpected{"line " + std::to_string(line_number + 1) + " is cut short"};
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(end + 1);
    line_number += 1;
    const std::string where = "line " + std::to_string(line_number);
    if (line_number == 1) {
      if (std::string(line) + "\n" != kWallTimesHeader)
        return Unexpected{where + ": expected the header " + std::string(kWallTimesHeader, 16)};
      continue;
    }
    const size_t comma = line.find(',');
    if (comma == std::string_view::npos) return Unexpected{where + ": expected iteration,wall_s"};
    WallTime w;
    const char* first = line.data();
    const auto [it_end, it_ec] = std::from_chars(first, first + comma, w.iteration);
    const auto [s_end, s_ec] = std::from_chars(first + comma + 1, first + line.size(), w.seconds);
    if (it_ec != std::errc() || it_end != first + comma || w.iteration < 0)
      return Unexpected{where + ": the iteration is not a non-negative integer"};
    if (s_ec != std::errc() || s_end != first + line.size() || !std::isfinite(w.seconds) || w.seconds < 0)
      return Unexpected{where + ": wall_s is not a finite, non-negative number"};
    if (!out.empty() && w.iteration <= out.back().iteration)
      return Unexpected{where + ": iteration " + std::to_string(w.iteration) + " does not follow " +
                        std::to_string(out.back().iteration)};
    if (!out.empty() && w.seconds < out.back().seconds) return Unexpected{where + ": the time goes back"};
    out.push_back(w);
  }
  if (line_number == 0) return Unexpected{"empty (no header)"};
  return out;
}

Expected<std::vector<WallTime>> read_wall_times(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, kMaxWallTimesBytes);
  if (!text) return Unexpected{text.error()};
  const size_t end = text->rfind('\n');
  text->resize(end == std::string::npos ? 0 : end + 1);
  return parse_wall_times(*text);
}

WallTimes WallTimes::open(const std::filesystem::path& dir, int next_iteration, std::string* warning) {
  const std::filesystem::path path = dir / kWallTimesFile;
  std::vector<WallTime> kept;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) {
    Expected<std::vector<WallTime>> lines = read_wall_times(path);
    if (lines) {
      for (const WallTime& w : *lines)
        if (w.iteration < next_iteration) kept.push_back(w);
    } else if (warning) {
      *warning = path.string() + ": " + lines.error() + "; the run's earlier wall times are lost, its clock restarts";
    }
  }
  const std::string text = wall_times_text(kept);
  const double carried = kept.empty() ? 0.0 : kept.back().seconds;
  if (auto error = write_file_atomically(path, text)) {
    // appending after lines the checkpoint did not keep would leave the file out of order: record nothing
    if (warning) *warning = path.string() + ": " + *error + "; wall times are not recorded";
    return WallTimes({}, carried);
  }
  return WallTimes(path, carried);
}

std::optional<std::string> WallTimes::record(int iteration, double seconds) {
  if (path_.empty()) return std::nullopt;  // open() could not rewrite the file and said so
  const int fd = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) return path_.string() + ": cannot open: " + std::generic_category().message(errno);
  const int err = write_all(fd, line_text(iteration, carried_ + seconds));
  ::close(fd);
  if (err != 0) return path_.string() + ": cannot write: " + std::generic_category().message(err);
  return std::nullopt;
}

}  // namespace poet
