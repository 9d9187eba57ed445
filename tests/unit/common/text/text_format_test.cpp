// Tests common/text/text_format: numbers that read back to their bits, zero-padded hex, peer ids.

#include "common/text/text_format.h"

#include <gtest/gtest.h>

#include <charconv>
#include <limits>
#include <string>

namespace poet {
namespace {

TEST(TextFormat, NumbersReadBackToTheSameBits) {
  EXPECT_EQ(number_text(0.1), "0.1");
  EXPECT_EQ(number_text(-0.0), "-0");
  EXPECT_EQ(number_text(1e300), "1e+300");
  EXPECT_EQ(number_text(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(number_text(int64_t{-42}), "-42");
  for (double x : {1.0 / 3, 2.5e-310, 123456789.125, -7.0}) {
    const std::string text = number_text(x);
    double back = 0;
    std::from_chars(text.data(), text.data() + text.size(), back);
    EXPECT_EQ(back, x) << text;
  }
}

TEST(TextFormat, HexIsZeroPaddedLowercase) {
  EXPECT_EQ(hex_text(0xdeadbeef), "00000000deadbeef");
  EXPECT_EQ(hex_text(0xDEADBEEF, 8), "deadbeef");
  EXPECT_EQ(hex_text(0xab, 2), "ab");
  EXPECT_EQ(hex_text(~uint64_t{0}), "ffffffffffffffff");
}

TEST(TextFormat, PeerIdsArePrintedAsIsOrInHex) {
  EXPECT_EQ(peer_id_text("worker-7"), "worker-7");
  EXPECT_EQ(peer_id_text(std::string("\0kE", 3)), "0x006b45");
  EXPECT_EQ(peer_id_text("a b"), "0x612062") << "a space is not printed as is";
  EXPECT_EQ(peer_id_text(""), "0x");
}

TEST(TextFormat, PrintfAppendsItsTextWholeHoweverLong) {
  std::string out = "a";
  append_printf(out, " %d %s", 7, "b");
  EXPECT_EQ(out, "a 7 b");
  append_printf(out, "%s", std::string(5000, 'x').c_str());
  EXPECT_EQ(out.size(), 5u + 5000u);
  append_printf(out, "%s", "");
  EXPECT_EQ(out.size(), 5005u);
}

}  // namespace
}  // namespace poet
