#pragma once
// SHA-256 (FIPS 180-4), small and dependency-free. Used to seal the model file's canonical payload so that an
// edited or truncated model is refused (docs/design/classification.md "Loading checks version and consistency"), and to
// fingerprint a training data set.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace wish {

class Sha256 {
 public:
  Sha256();
  void update(std::string_view bytes);
  std::array<std::uint8_t, 32> finish();  // the object must not be updated afterwards
  static std::string hex(std::string_view bytes);  // lowercase hex digest of `bytes`

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;  // bytes
};

}  // namespace wish
