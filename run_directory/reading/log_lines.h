#pragma once
// The whole lines of a run log's bytes. The run appends whole lines, so bytes after the last newline are a line
// still being written (a live log) or damage (a log a checkpoint vouches for): the caller decides which.

#include <cstddef>
#include <string_view>
#include <vector>

namespace poet {

struct LogLines {
  std::vector<std::string_view> lines;  // without their '\n', viewing the bytes given
  size_t consumed = 0;                  // bytes up to and with the last newline
};

LogLines whole_lines(std::string_view bytes);

}  // namespace poet
