#pragma once
// Numbers and ids as text, each written one way everywhere: in files, messages and logs.

#include <cstdarg>
#include <cstdint>
#include <string>
#include <string_view>

namespace poet {

// The shortest decimal form that reads back to the same bits ("0.1", "1e+300", "-0", "inf", "nan").
std::string number_text(double value);
std::string number_text(int64_t value);
// A number for a person reading a log: whole numbers as integers, two decimals from 1 up, four significant digits
// below (a score 229.96, a novelty 0.09628, a learning rate 0.009975); the files keep every digit.
std::string reading_text(double value);

// `digits` lowercase hex digits, zero-padded ("00000000deadbeef" for hex_text(0xdeadbeef, 16)).
std::string hex_text(uint64_t value, int digits = 16);

// A peer's id (ZeroMQ routing ids are bytes): as is when printable ASCII, else "0x" and its bytes in hex.
std::string peer_id_text(std::string_view id);

// printf's format into a string: the tables people read (poet-report's, poetctl's), checked by the compiler as
// printf is.
std::string vprintf_text(const char* format, va_list args);
[[gnu::format(printf, 2, 3)]] void append_printf(std::string& out, const char* format, ...);

}  // namespace poet
