// libFuzzer target for the label-volume readers (NIfTI-1, gzip-wrapped NIfTI-1, TIFF): any bytes must be read or
// refused with a WishError, with no sanitizer report. A small voxel limit keeps each run fast.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/common/errors.hpp"
#include "core/io/volume_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  wish::VolumeReadOptions options;
  options.limits.max_voxels = 1 << 20;
  options.limits.max_pages = 256;
  try {
    (void)wish::read_volume(std::string_view(reinterpret_cast<const char*>(data), size), options);
  } catch (const wish::WishError&) {
    // Refusing is fine; anything else is a bug.
  }
  return 0;
}
