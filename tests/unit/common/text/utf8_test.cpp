// Tests common/text/utf8: well-formed UTF-8 accepted; stray, overlong, surrogate, out-of-range and cut sequences
// refused, and replaced by '?' byte by byte in valid_utf8; control characters written out by printable_text.

#include "common/text/utf8.h"

#include <gtest/gtest.h>

#include <string>

namespace poet {
namespace {

TEST(Utf8, WellFormedTextIsAccepted) {
  for (const char* text : {"", "flat", "r0.5.p0.0_0.8", "σ = 0.05", "€", "\xf0\x9f\x9a\xb6 walker", "\xf4\x8f\xbf\xbf"})
    EXPECT_TRUE(is_valid_utf8(text)) << text;
}

TEST(Utf8, MalformedBytesAreRefused) {
  for (const std::string& text : {std::string("\xff"), std::string("bad \xff\xfe name"), std::string("\x80"),
                                  std::string("\xc0\xaf"),          // overlong '/'
                                  std::string("\xe0\x80\xaf"),      // overlong, three bytes
                                  std::string("\xed\xa0\x80"),      // a UTF-16 surrogate
                                  std::string("\xf4\x90\x80\x80"),  // past U+10FFFF
                                  std::string("\xe2\x82"),          // cut short
                                  std::string("\xe2\x28\xa1")})     // a continuation byte missing
    EXPECT_FALSE(is_valid_utf8(text)) << testing::PrintToString(text);
}

TEST(Utf8, ValidUtf8KeepsWellFormedTextAndMarksEachBadByte) {
  EXPECT_EQ(valid_utf8("σ = 0.05 \xf0\x9f\x9a\xb6"), "σ = 0.05 \xf0\x9f\x9a\xb6");
  EXPECT_EQ(valid_utf8("bad \xff\xfe name"), "bad ?? name");
  EXPECT_EQ(valid_utf8("\xc0\xaf"), "??");       // overlong
  EXPECT_EQ(valid_utf8("\xed\xa0\x80"), "???");  // a surrogate
  EXPECT_EQ(valid_utf8("x\xe2\x82"), "x??");     // cut short
  EXPECT_TRUE(is_valid_utf8(valid_utf8("\xe2\x28\xa1\xf4\x90\x80\x80")));
}

TEST(Utf8, PrintableTextWritesOutControlCharactersOnly) {
  EXPECT_EQ(printable_text("σ = 0.05\tline\n"), "σ = 0.05\tline\n");
  // a window title, a screen clear, a carriage return that would hide the line, DEL
  EXPECT_EQ(printable_text("\x1b]0;pwned\x07\x1b[2Jx\ry\x7f"), "\\u001b]0;pwned\\u0007\\u001b[2Jx\\u000dy\\u007f");
  EXPECT_EQ(printable_text(std::string("a\0b", 3)), "a\\u0000b");
  // C1 controls as UTF-8 (CSI is U+009B), and as stray bytes (not UTF-8: '?')
  EXPECT_EQ(printable_text("\xc2\x9b"
                           "31m \xc2\x85 \xc2\xa0"),
            "\\u009b31m \\u0085 \xc2\xa0");
  EXPECT_EQ(printable_text("\x9b"
                           "31m"),
            "?31m");
  // within a JSON string the escape means the same character
  EXPECT_EQ(printable_text("{\"run\":\"\x1b[31m\"}"), "{\"run\":\"\\u001b[31m\"}");
}

}  // namespace
}  // namespace poet
