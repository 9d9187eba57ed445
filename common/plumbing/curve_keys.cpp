#include "common/plumbing/curve_keys.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include "common/plumbing/text_file.h"

namespace poet {
namespace {

constexpr size_t kZ85KeyLength = 40;
constexpr std::uintmax_t kMaxKeyFileBytes = 4096;
constexpr std::string_view kZ85Alphabet =
    "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ.-:+=^!/*?&<>()[]{}@%$#";

// Creates path with `mode` and writes text, failing when it exists (O_EXCL: no key is ever replaced).
std::optional<std::string> create_file(const std::filesystem::path& path, std::string_view text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) return path.string() + ": " + std::strerror(errno);
  const int error = write_all(fd, text);
  const int sync_error = error == 0 ? fsync_retrying(fd) : 0;
  ::close(fd);
  if (error != 0 || sync_error != 0) return path.string() + ": " + std::strerror(error != 0 ? error : sync_error);
  return std::nullopt;
}

}  // namespace

bool is_z85_key(std::string_view text) {
  return text.size() == kZ85KeyLength &&
         std::all_of(text.begin(), text.end(), [](char c) { return kZ85Alphabet.find(c) != std::string_view::npos; });
}

Expected<std::string> read_key_file(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, kMaxKeyFileBytes);
  if (!text) return Unexpected{path.string() + ": " + text.error()};
  std::string key = std::move(*text);
  if (key.ends_with('\n')) key.pop_back();
  if (key.ends_with('\r')) key.pop_back();  // a file written on Windows, or copied through it
  if (!is_z85_key(key))
    return Unexpected{path.string() + ": not a CURVE key (expected 40 characters of Z85 text on one line)"};
  return key;
}

Expected<CurveKeyPair> read_key_pair(const std::filesystem::path& dir, std::string_view name) {
  const std::string base(name);
  Expected<std::string> public_key = read_key_file(dir / (base + ".key"));
  if (!public_key) return Unexpected{public_key.error()};
  Expected<std::string> secret_key = read_key_file(dir / (base + ".key_secret"));
  if (!secret_key) return Unexpected{secret_key.error()};
  return CurveKeyPair{std::move(*public_key), std::move(*secret_key)};
}

std::optional<std::string> write_key_pair(const std::filesystem::path& dir, std::string_view name,
                                          const CurveKeyPair& keys) {
  if (!is_z85_key(keys.public_key) || !is_z85_key(keys.secret_key)) return "not a pair of Z85 CURVE keys";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return dir.string() + ": " + ec.message();
  const std::string base(name);
  const std::filesystem::path secret = dir / (base + ".key_secret");
  const std::filesystem::path public_key = dir / (base + ".key");
  // both checked before either is written: a new secret beside an old public key would be a pair that does not match
  for (const std::filesystem::path& path : {secret, public_key}) {
    if (std::filesystem::symlink_status(path, ec).type() == std::filesystem::file_type::not_found) continue;
    return path.string() + ": " + (ec ? ec.message() : std::strerror(EEXIST)) +
           " (no key is replaced: remove both files of the pair to make another)";
  }
  // the secret first: a pair with no public half is harmless, a public key without its secret is useless
  if (auto error = create_file(secret, keys.secret_key + "\n", 0600)) return error;
  if (auto error = create_file(public_key, keys.public_key + "\n", 0644)) {
    std::filesystem::remove(secret, ec);  // the public key came between the check and now: leave no half pair
    return error;
  }
  sync_directory(dir);
  return std::nullopt;
}

Expected<AuthorizedKeys> scan_authorized_keys(const std::filesystem::path& dir) {
  const std::filesystem::path folder = dir / "authorized";
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec))
    return Unexpected{folder.string() + ": no such folder (it holds the public keys of the authorised workers)"};
  AuthorizedKeys found;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
    if (entry.path().extension() != ".key") continue;
    Expected<std::string> key = read_key_file(entry.path());
    if (key) {
      found.keys.push_back(std::move(*key));
    } else {
      found.bad_files[entry.path().string()] = key.error();
    }
  }
  if (ec) return Unexpected{folder.string() + ": " + ec.message()};
  std::sort(found.keys.begin(), found.keys.end());
  return found;
}

}  // namespace poet
