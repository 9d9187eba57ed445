#include "run_directory/reading/log_lines.h"

namespace poet {

LogLines whole_lines(std::string_view bytes) {
  LogLines out;
  size_t start = 0;
  for (size_t newline; (newline = bytes.find('\n', start)) != std::string_view::npos; start = newline + 1)
    out.lines.push_back(bytes.substr(start, newline - start));
  out.consumed = start;
  return out;
}

}  // namespace poet
