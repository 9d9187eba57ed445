#include "common/plumbing/text_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <string>
#include <thread>

#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr auto kDeadline = 10s;  // a read that does not block returns in microseconds

// Runs body on another thread. If it has not returned by the deadline the test fails, and a writer is opened on
// fifo so that a reader blocked in open() gets out (the test then ends instead of hanging).
template <class Body>
auto within_deadline(Body body, const fs::path& fifo) {
  auto done = std::async(std::launch::async, std::move(body));
  if (done.wait_for(kDeadline) == std::future_status::timeout) {
    ADD_FAILURE() << "still blocked after " << kDeadline.count() << " s";
    while (done.wait_for(100ms) == std::future_status::timeout) {
      // fails with ENXIO until the reader is inside open(); closing at once makes its read see end of file
      const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
      if (fd >= 0) ::close(fd);
    }
  }
  return done.get();
}

// A fresh directory per test, removed even when the test fails.
class TextFileTest : public ::testing::Test {
 protected:
  fs::path write(const std::string& name, const std::string& text) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  fs::path fifo(const std::string& name) {
    const fs::path path = dir_ / name;
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << std::strerror(errno);
    return path;
  }
  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
};

TEST_F(TextFileTest, ReadsARegularFileWhole) {
  // several read() calls' worth, with every byte value
  std::string text;
  for (int i = 0; i < 200'000; ++i) text.push_back(static_cast<char>(i * 7 % 256));
  const Expected<std::string> read = read_text_file(write("big.bin", text), 1 << 20);
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(*read, text);

  const Expected<std::string> empty = read_text_file(write("empty.txt", ""), 10);
  ASSERT_TRUE(empty) << empty.error();
  EXPECT_EQ(*empty, "");
}

TEST_F(TextFileTest, ReadsAFileOfExactlyTheLimit) {
  const Expected<std::string> read = read_text_file(write("ten.txt", "0123456789"), 10);
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(*read, "0123456789");
}

TEST_F(TextFileTest, RefusesAFileOverTheLimit) {
  const Expected<std::string> read = read_text_file(write("eleven.txt", "0123456789a"), 10);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error(), "is larger than 10 bytes");
  const Expected<std::string> big = read_text_file(write("big.txt", std::string(200'000, 'x')), 65'536);
  ASSERT_FALSE(big);
  EXPECT_EQ(big.error(), "is larger than 65536 bytes");
}

// Files whose size reads 0 (those of /proc) are read to their end all the same, within the limit.
TEST_F(TextFileTest, ReadsAFileThatReportsSizeZero) {
  const fs::path proc = "/proc/self/status";
  if (!fs::exists(proc)) GTEST_SKIP() << proc << " does not exist here";
  const Expected<std::string> read = read_text_file(proc, 1 << 20);
  ASSERT_TRUE(read) << read.error();
  EXPECT_NE(read->find("Name:"), std::string::npos) << *read;
  const Expected<std::string> small = read_text_file(proc, 4);
  ASSERT_FALSE(small);
  EXPECT_EQ(small.error(), "is larger than 4 bytes");
}

TEST_F(TextFileTest, FollowsASymbolicLinkToARegularFile) {
  const fs::path target = write("target.txt", "hello");
  fs::create_symlink(target, dir_ / "link.txt");
  const Expected<std::string> read = read_text_file(dir_ / "link.txt", 100);
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(*read, "hello");
}

TEST_F(TextFileTest, RefusesAMissingFile) {
  EXPECT_EQ(read_text_file(dir_ / "missing.txt", 100).error(), "does not exist");
  // a path through a regular file (ENOTDIR) does not exist either
  const fs::path file = write("file.txt", "x");
  EXPECT_EQ(read_text_file(file / "inside.txt", 100).error(), "does not exist");
  // a dangling symbolic link
  fs::create_symlink(dir_ / "nowhere.txt", dir_ / "dangling.txt");
  EXPECT_EQ(read_text_file(dir_ / "dangling.txt", 100).error(), "does not exist");
}

TEST_F(TextFileTest, PathExistsTellsAbsenceFromAnError) {
  EXPECT_TRUE(*path_exists(write("file.txt", "x")));
  EXPECT_TRUE(*path_exists(dir_));
  EXPECT_FALSE(*path_exists(dir_ / "missing.txt"));
  fs::create_symlink(dir_ / "nowhere.txt", dir_ / "dangling.txt");
  EXPECT_FALSE(*path_exists(dir_ / "dangling.txt"));
  // a symbolic-link loop is not absence: the caller would say "does not exist" of a file that is there
  fs::create_symlink(dir_ / "loop-b", dir_ / "loop-a");
  fs::create_symlink(dir_ / "loop-a", dir_ / "loop-b");
  const Expected<bool> loop = path_exists(dir_ / "loop-a");
  ASSERT_FALSE(loop);
  EXPECT_EQ(loop.error().rfind("cannot access: ", 0), 0u) << loop.error();
}

TEST_F(TextFileTest, RefusesADirectory) {
  const Expected<std::string> read = read_text_file(dir_, 100);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error(), "is a directory");
}

// No writer is ever opened on the FIFO: opening it for reading without O_NONBLOCK would wait forever.
TEST_F(TextFileTest, RefusesAFifoWithoutWaiting) {
  const fs::path path = fifo("config.fifo");
  const auto start = std::chrono::steady_clock::now();
  const Expected<std::string> read = within_deadline([&] { return read_text_file(path, 1 << 20); }, path);
  EXPECT_LT(std::chrono::steady_clock::now() - start, 2s);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error(), "is not a regular file (a FIFO)");
}

// The path is swapped between a regular file and a FIFO while it is read, so that some reads find the file at
// stat() and the FIFO at open(): every read must return at once, with the file's text or the FIFO's refusal.
TEST_F(TextFileTest, RefusesAFifoSwappedInAfterTheCheck) {
  const fs::path file = write("file.txt", "text");
  const fs::path pipe_path = fifo("pipe.fifo");
  const fs::path link = dir_ / "swapped";
  fs::create_symlink(file, link);

  std::atomic<bool> stop{false};
  std::thread swapper([&] {
    // rename() replaces the link atomically, so the path always names one or the other
    for (int i = 0; !stop; ++i) {
      const fs::path tmp = dir_ / "swapped.tmp";
      std::error_code ec;
      fs::remove(tmp, ec);
      fs::create_symlink(i % 2 ? pipe_path : file, tmp, ec);
      if (!ec) fs::rename(tmp, link, ec);
    }
  });
  struct Counts {
    int text = 0, fifo = 0, other = 0;
    std::string last_other;
  };
  const Counts counts = within_deadline(
      [&] {
        Counts c;
        for (int i = 0; i < 3000; ++i) {
          const Expected<std::string> read = read_text_file(link, 100);
          if (read && *read == "text") {
            ++c.text;
          } else if (!read && read.error() == "is not a regular file (a FIFO)") {
            ++c.fifo;
          } else {
            ++c.other;
            c.last_other = read ? "text \"" + *read + "\"" : read.error();
          }
        }
        return c;
      },
      pipe_path);
  stop = true;
  swapper.join();
  EXPECT_EQ(counts.other, 0) << counts.last_other;
  EXPECT_GT(counts.text + counts.fifo, 0);
}

TEST_F(TextFileTest, RefusesCharacterDevices) {
  for (const char* device : {"/dev/null", "/dev/zero"}) {
    if (!fs::exists(device)) continue;
    const Expected<std::string> read = read_text_file(device, 1 << 20);
    ASSERT_FALSE(read) << device;
    EXPECT_EQ(read.error(), "is not a regular file (a character device)") << device;
  }
}

TEST_F(TextFileTest, RefusesASocket) {
  const fs::path path = dir_ / "socket";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0) << std::strerror(errno);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.string().size(), sizeof address.sun_path) << path;
  std::strncpy(address.sun_path, path.c_str(), sizeof address.sun_path - 1);
  const int bound = ::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  const int bind_errno = errno;
  ::close(fd);
  ASSERT_EQ(bound, 0) << std::strerror(bind_errno);
  const Expected<std::string> read = read_text_file(path, 100);
  ASSERT_FALSE(read);
  EXPECT_EQ(read.error(), "is not a regular file (a socket)");
}

}  // namespace
}  // namespace poet
