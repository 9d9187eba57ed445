#include "run_directory/files/crc32.h"

#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

namespace poet {

uint32_t crc32_extend(uint32_t crc, std::string_view bytes) {
  uLong value = crc;
  // zlib takes a uInt length: longer inputs go in pieces
  constexpr size_t kPiece = size_t{1} << 30;
  for (size_t offset = 0; offset < bytes.size(); offset += kPiece) {
    const size_t n = std::min(kPiece, bytes.size() - offset);
    value = ::crc32(value, reinterpret_cast<const Bytef*>(bytes.data() + offset), static_cast<uInt>(n));
  }
  return static_cast<uint32_t>(value);
}

Expected<uint32_t> file_prefix_crc32(const std::filesystem::path& path, int64_t size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Unexpected{path.string() + ": cannot read"};
  std::vector<char> buffer(size_t{1} << 20);
  uint32_t crc = 0;
  for (int64_t left = size; left > 0;) {
    const auto n = static_cast<std::streamsize>(std::min<int64_t>(left, static_cast<int64_t>(buffer.size())));
    if (!in.read(buffer.data(), n))
      return Unexpected{path.string() + ": shorter than the " + std::to_string(size) +
                        " bytes the checkpoint has seen"};
    crc = crc32_extend(crc, std::string_view(buffer.data(), static_cast<size_t>(n)));
    left -= n;
  }
  return crc;
}

}  // namespace poet
