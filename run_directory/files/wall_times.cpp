#include "run_directory/files/wall_times.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "common/plumbing/text_file.h"

namespace poet {
namespace {

std::string line_text(const WallTime& w) {
  char buffer[192];
  int n = std::snprintf(buffer, sizeof buffer, "%d,%.3f", w.iteration, w.seconds);
  if (w.phases)
    n += std::snprintf(buffer + n, sizeof buffer - static_cast<size_t>(n), ",%.3f,%.3f,%.3f,%.3f", (*w.phases)[0],
                       (*w.phases)[1], (*w.phases)[2], (*w.phases)[3]);
  if (w.phases && w.waiting)
    n += std::snprintf(buffer + n, sizeof buffer - static_cast<size_t>(n), ",%.3f", *w.waiting);
  return std::string(buffer, static_cast<size_t>(n)) + "\n";
}

// A finite, non-negative number filling the field.
bool parse_seconds(std::string_view field, double& out) {
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), out);
  return ec == std::errc() && end == field.data() + field.size() && std::isfinite(out) && out >= 0;
}

}  // namespace

std::string wall_times_text(const std::vector<WallTime>& lines) {
  std::string text = kWallTimesHeader;
  for (const WallTime& w : lines) text += line_text(w);
  return text;
}

namespace {

// parse_wall_times into `out`, which holds the lines read before the error when there is one (its message).
std::optional<std::string> parse_lines(std::string_view text, std::vector<WallTime>& out) {
  size_t line_number = 0;
  size_t most_fields = 2;  // the header's
  while (!text.empty()) {
    const size_t end = text.find('\n');
    if (end == std::string_view::npos) return "line " + std::to_string(line_number + 1) + " is cut short";
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(end + 1);
    line_number += 1;
    const std::string where = "line " + std::to_string(line_number);
    if (line_number == 1) {
      const std::string header = std::string(line) + "\n";
      if (header != kWallTimesHeader && header != kWallTimesHeaderWithoutWaiting &&
          header != kWallTimesHeaderWithoutPhases)
        return where + ": expected the header " + std::string(kWallTimesHeader, sizeof kWallTimesHeader - 2);
      most_fields = header == kWallTimesHeader ? 7 : header == kWallTimesHeaderWithoutWaiting ? 6 : 2;
      continue;
    }
    std::vector<std::string_view> fields;
    for (size_t at = 0;;) {
      const size_t comma = line.find(',', at);
      fields.push_back(line.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at));
      if (comma == std::string_view::npos) break;
      at = comma + 1;
    }
    // a line has the fields of its build: iteration,wall_s; then every phase's seconds; then waiting_s
    if ((fields.size() != 2 && fields.size() != 6 && fields.size() != 7) || fields.size() > most_fields)
      return where + ": expected " +
             std::string(most_fields == 7   ? "iteration,wall_s, every phase's seconds too, or waiting_s too"
                         : most_fields == 6 ? "iteration,wall_s or every phase's seconds too"
                                            : "iteration,wall_s");
    WallTime w;
    const auto [it_end, it_ec] = std::from_chars(fields[0].data(), fields[0].data() + fields[0].size(), w.iteration);
    if (it_ec != std::errc() || it_end != fields[0].data() + fields[0].size() || w.iteration < 0)
      return where + ": the iteration is not a non-negative integer";
    if (!parse_seconds(fields[1], w.seconds)) return where + ": wall_s is not a finite, non-negative number";
    if (fields.size() >= 6) {
      w.phases.emplace();
      for (size_t p = 0; p < 4; ++p)
        if (!parse_seconds(fields[2 + p], (*w.phases)[p]))
          return where + ": field " + std::to_string(3 + p) + " is not a finite, non-negative number";
    }
    if (fields.size() == 7 && !parse_seconds(fields[6], w.waiting.emplace()))
      return where + ": waiting_s is not a finite, non-negative number";
    if (!out.empty() && w.iteration <= out.back().iteration)
      return where + ": iteration " + std::to_string(w.iteration) + " does not follow " +
             std::to_string(out.back().iteration);
    if (!out.empty() && w.seconds < out.back().seconds) return where + ": the time goes back";
    out.push_back(w);
  }
  if (line_number == 0) return "empty (no header)";
  return std::nullopt;
}

}  // namespace

Expected<std::vector<WallTime>> parse_wall_times(std::string_view text, std::vector<WallTime>* valid_prefix) {
  std::vector<WallTime> lines;
  if (std::optional<std::string> error = parse_lines(text, lines)) {
    if (valid_prefix) *valid_prefix = std::move(lines);
    return Unexpected{std::move(*error)};
  }
  return lines;
}

Expected<std::vector<WallTime>> read_wall_times(const std::filesystem::path& path,
                                                std::vector<WallTime>* valid_prefix) {
  Expected<std::string> text = read_text_file(path, kMaxWallTimesBytes);
  if (!text) return Unexpected{text.error()};
  const size_t end = text->rfind('\n');
  text->resize(end == std::string::npos ? 0 : end + 1);
  return parse_wall_times(*text, valid_prefix);
}

WallTimes WallTimes::open(const std::filesystem::path& dir, int next_iteration, std::string* warning) {
  const std::filesystem::path path = dir / kWallTimesFile;
  std::vector<WallTime> kept;
  const Expected<bool> exists = path_exists(path);
  if (!exists) {
    // what is there may hold the run's times: neither read nor replaced
    if (warning) *warning = path.string() + ": " + exists.error() + "; wall times are not recorded";
    return WallTimes({}, 0.0);
  }
  if (*exists) {
    std::vector<WallTime> valid;  // on a damaged file, the lines before the damage
    Expected<std::vector<WallTime>> lines = read_wall_times(path, &valid);
    if (lines) valid = std::move(*lines);
    for (const WallTime& w : valid)
      if (w.iteration < next_iteration) kept.push_back(w);
    if (!lines && warning)
      *warning = path.string() + ": " + lines.error() +
                 (kept.empty() ? "; the run's earlier wall times are lost, its clock restarts"
                               : "; the lines from there on are dropped, the clock goes on from iteration " +
                                     std::to_string(kept.back().iteration));
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

std::optional<std::string> WallTimes::record(int iteration, double seconds, const PhaseSeconds& phases,
                                             double waiting) {
  if (path_.empty()) return std::nullopt;  // open() could not rewrite the file and said so
  const int fd = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd < 0) return path_.string() + ": cannot open: " + std::generic_category().message(errno);
  const int err = write_all(fd, line_text({iteration, carried_ + seconds, phases, waiting}));
  ::close(fd);
  if (err != 0) return path_.string() + ": cannot write: " + std::generic_category().message(err);
  return std::nullopt;
}

}  // namespace poet
