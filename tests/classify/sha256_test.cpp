#include <gtest/gtest.h>

#include <string>

#include "core/classify/sha256.hpp"

namespace wish {

TEST(Sha256, KnownVectors) {  // FIPS 180-4 examples
  EXPECT_EQ(Sha256::hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256::hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256::hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256::hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, IncrementalEqualsOneShot) {
  const std::string text(777, 'x');
  Sha256 sha;
  for (std::size_t i = 0; i < text.size(); i += 61) sha.update(std::string_view(text).substr(i, 61));
  const auto digest = sha.finish();
  std::string hex;
  const char* d = "0123456789abcdef";
  for (auto b : digest) {
    hex += d[b >> 4];
    hex += d[b & 15];
  }
  EXPECT_EQ(hex, Sha256::hex(text));
}

}  // namespace wish
