// Base64 (wire/base64.hpp) against RFC 4648 §10's test vectors, and every byte value once: the decoding by hand of
// the output (a 6-bit table lookup) must give the input back.
#include <gtest/gtest.h>

#include <string>

#include "wire/base64.hpp"

namespace wish::wire {
namespace {

TEST(Base64, Rfc4648TestVectors) {
  EXPECT_EQ(base64_encode(""), "");
  EXPECT_EQ(base64_encode("f"), "Zg==");
  EXPECT_EQ(base64_encode("fo"), "Zm8=");
  EXPECT_EQ(base64_encode("foo"), "Zm9v");
  EXPECT_EQ(base64_encode("foob"), "Zm9vYg==");
  EXPECT_EQ(base64_encode("fooba"), "Zm9vYmE=");
  EXPECT_EQ(base64_encode("foobar"), "Zm9vYmFy");
}

TEST(Base64, EveryByteValueRoundTrips) {
  std::string bytes;
  for (int b = 0; b < 256; ++b) bytes += static_cast<char>(b);
  const std::string text = base64_encode(bytes);
  const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string back;
  unsigned bits = 0, value = 0;
  for (char c : text) {
    if (c == '=') break;
    value = value << 6 | static_cast<unsigned>(alphabet.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      back += static_cast<char>(value >> bits & 0xff);
    }
  }
  EXPECT_EQ(back, bytes);
  EXPECT_EQ(text.size(), 344u);  // 256 bytes: 86 groups of 4
}

}  // namespace
}  // namespace wish::wire
