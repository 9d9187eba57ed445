// Tests common/plumbing/curve_keys.cpp: Z85 keys checked, pairs written with the secret private and never replaced (nor
// half of one completed), and every kind of bad key file refused with its name.

#include "common/plumbing/curve_keys.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

constexpr char kPublic[] = "rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7";
constexpr char kSecret[] = "JTKVSB%%)wK0E.X)V>+}o?pNmC{O&4W4b!Ni{Lh6";

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

class CurveKeysTest : public ::testing::Test {
 protected:
  poet::testing::ScratchDir scratch_{"poet_curve_keys_test"};
  fs::path dir_ = scratch_.path() / "keys";  // not there yet: writing a pair makes it
};

TEST_F(CurveKeysTest, Z85KeysAreFortyCharactersOfTheAlphabet) {
  EXPECT_TRUE(is_z85_key(kPublic));
  EXPECT_FALSE(is_z85_key(std::string(kPublic).substr(1)));
  EXPECT_FALSE(is_z85_key(std::string(kPublic) + "0"));
  std::string spaced = kPublic;
  spaced[3] = ' ';
  EXPECT_FALSE(is_z85_key(spaced));
  spaced[3] = '"';  // not in Z85
  EXPECT_FALSE(is_z85_key(spaced));
}

TEST_F(CurveKeysTest, APairIsWrittenReadBackAndNeverReplaced) {
  ASSERT_EQ(write_key_pair(dir_, "worker", {kPublic, kSecret}), std::nullopt);
  EXPECT_EQ(fs::status(dir_ / "worker.key_secret").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write);
  const Expected<CurveKeyPair> read = read_key_pair(dir_, "worker");
  ASSERT_TRUE(read) << read.error();
  EXPECT_EQ(read->public_key, kPublic);
  EXPECT_EQ(read->secret_key, kSecret);
  const std::optional<std::string> again = write_key_pair(dir_, "worker", {kSecret, kPublic});
  ASSERT_TRUE(again);
  EXPECT_TRUE(contains(*again, "worker.key_secret")) << *again;
  EXPECT_EQ(read_key_pair(dir_, "worker")->secret_key, kSecret) << "the existing key stays";
  EXPECT_TRUE(write_key_pair(dir_, "other", {"short", kSecret}));
}

TEST_F(CurveKeysTest, HalfAPairLeftIsNotCompletedWithAKeyThatDoesNotMatch) {
  // only the public half (or only the secret, or a dangling link) is there: nothing is written, the error names it
  fs::create_directories(dir_);
  for (const std::string present : {"worker.key", "worker.key_secret"}) {
    std::ofstream(dir_ / present) << kPublic << "\n";
    const std::optional<std::string> error = write_key_pair(dir_, "worker", {kPublic, kSecret});
    ASSERT_TRUE(error) << present;
    EXPECT_TRUE(contains(*error, present)) << *error;
    EXPECT_TRUE(contains(*error, "exists")) << *error;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1) << "only " << present;
    fs::remove(dir_ / present);
  }
  fs::create_symlink(dir_ / "nowhere", dir_ / "worker.key");
  ASSERT_TRUE(write_key_pair(dir_, "worker", {kPublic, kSecret}));
  EXPECT_FALSE(fs::exists(fs::symlink_status(dir_ / "worker.key_secret")));
}

TEST_F(CurveKeysTest, BadKeyFilesAreRefusedWithTheirName) {
  fs::create_directories(dir_);
  const Expected<std::string> missing = read_key_file(dir_ / "none.key");
  ASSERT_FALSE(missing);
  EXPECT_TRUE(contains(missing.error(), "none.key")) << missing.error();
  for (const std::string& text : {std::string(), std::string("not a key\n"), std::string(kPublic) + "\n\n",
                                  std::string(kPublic) + " ", std::string(5000, 'a')}) {
    std::ofstream(dir_ / "bad.key", std::ios::trunc) << text;
    const Expected<std::string> key = read_key_file(dir_ / "bad.key");
    ASSERT_FALSE(key) << "accepted: " << text;
    EXPECT_TRUE(contains(key.error(), "bad.key")) << key.error();
  }
  std::ofstream(dir_ / "good.key", std::ios::trunc) << kPublic;  // no newline is fine
  EXPECT_TRUE(read_key_file(dir_ / "good.key"));
}

TEST_F(CurveKeysTest, AuthorizedKeysAreTheFolderKeyFiles) {
  const Expected<AuthorizedKeys> no_folder = scan_authorized_keys(dir_);
  ASSERT_FALSE(no_folder);
  EXPECT_TRUE(contains(no_folder.error(), "authorized")) << no_folder.error();
  fs::create_directories(dir_ / "authorized");
  EXPECT_TRUE(scan_authorized_keys(dir_)->keys.empty());
  std::ofstream(dir_ / "authorized" / "b.key") << kSecret << "\n";
  std::ofstream(dir_ / "authorized" / "a.key") << kPublic << "\n";
  std::ofstream(dir_ / "authorized" / "README") << "other files are ignored\n";
  const Expected<AuthorizedKeys> found = scan_authorized_keys(dir_);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->keys, (std::vector<std::string>{kSecret, kPublic}));  // sorted
  EXPECT_TRUE(found->bad_files.empty());
}

TEST_F(CurveKeysTest, AScanSetsFilesThatHoldNoKeyAside) {
  EXPECT_FALSE(scan_authorized_keys(dir_));  // no folder
  fs::create_directories(dir_ / "authorized");
  std::ofstream(dir_ / "authorized" / "a.key") << kPublic << "\n";
  std::ofstream(dir_ / "authorized" / "half.key") << std::string(kPublic).substr(0, 20);  // half-copied
  std::ofstream(dir_ / "authorized" / "junk.key") << "\x01\x02 garbage";
  const Expected<AuthorizedKeys> found = scan_authorized_keys(dir_);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->keys, std::vector<std::string>{kPublic});
  ASSERT_EQ(found->bad_files.size(), 2u);
  const std::string half = (dir_ / "authorized" / "half.key").string();
  ASSERT_TRUE(found->bad_files.contains(half));
  EXPECT_TRUE(contains(found->bad_files.at(half), "half.key: not a CURVE key")) << found->bad_files.at(half);
}

TEST_F(CurveKeysTest, AKeyFileWithCrlfLineEndsHoldsItsKey) {
  fs::create_directories(dir_ / "authorized");
  std::ofstream(dir_ / "authorized" / "windows.key") << kPublic << "\r\n";
  const Expected<AuthorizedKeys> found = scan_authorized_keys(dir_);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->keys, std::vector<std::string>{kPublic});
  EXPECT_TRUE(found->bad_files.empty());
}

}  // namespace
}  // namespace poet
