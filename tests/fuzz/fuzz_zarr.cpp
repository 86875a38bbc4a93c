// libFuzzer target for the OME-Zarr reader (core/io/zarr_*): the store metadata (.zattrs, .zarray: labels, levels,
// axes, scales, dtype, order, fill_value) and chunk decoding (zlib, gzip, zstd, blosc). Input starting "PK" is read as
// an uploaded zip (read_volume); any other input is a store of records "key=value" separated by "\x00\x01\x02\x03",
// so the fuzzer mutates the JSON and the chunks directly instead of breaking a zip's checksums. Any bytes must be read
// or refused with a WishError, with no sanitizer report; a small voxel limit keeps each run fast.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"
#include "core/io/zarr_metadata.hpp"

namespace {

class RecordStore final : public wish::io_detail::ZarrStore {
 public:
  explicit RecordStore(std::string_view input) {
    constexpr std::string_view kSeparator("\x00\x01\x02\x03", 4);
    while (!input.empty()) {
      const std::size_t end = std::min(input.find(kSeparator), input.size());
      const std::string_view record = input.substr(0, end);
      const std::size_t eq = record.find('=');
      if (eq != std::string_view::npos) values_[std::string(record.substr(0, eq))] = std::string(record.substr(eq + 1));
      input.remove_prefix(std::min(end + kSeparator.size(), input.size()));
    }
  }
  std::optional<std::string> get(const std::string& key, std::uint64_t max_bytes) const override {
    const auto it = values_.find(key);
    if (it == values_.end()) return std::nullopt;
    if (it->second.size() > max_bytes) throw wish::LimitExceededError("value too large", {});
    return it->second;
  }

 private:
  std::map<std::string, std::string> values_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  wish::VolumeReadOptions options;
  options.limits.max_voxels = 1 << 18;
  try {
    if (bytes.starts_with("PK")) (void)wish::read_volume(bytes, options);
    else (void)wish::io_detail::read_zarr(RecordStore(bytes), options);
  } catch (const wish::WishError&) {
    // Refusing is fine; anything else is a bug.
  }
  return 0;
}
