#pragma once
// The body shared by the reader fuzz targets (fuzz_<format>.cpp): any bytes must be read or refused with a
// WishError, with no sanitizer report. Small limits keep each run fast; the format hint is the target's format and,
// when the content is read, the mesh is also analysed and prepared, so the validation code sees hostile meshes too.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/common/errors.hpp"
#include "core/io/mesh_io.hpp"
#include "core/validation/mesh_report.hpp"

namespace wish::fuzz {

inline int fuzz_reader(wish::MeshFormat hint, const std::uint8_t* data, std::size_t size) {
  wish::ReadOptions options;
  options.hint = hint;
  options.limits.max_vertices = 100'000;
  options.limits.max_faces = 200'000;
  options.limits.max_line_length = 1 << 16;
  try {
    const wish::ReadResult result = wish::read_mesh(std::string_view(reinterpret_cast<const char*>(data), size), options);
    (void)wish::prepare_for_mapping(result.mesh);
  } catch (const wish::WishError&) {
    // Refusing is fine; anything else (another exception, a crash, a sanitizer report) is a bug.
  }
  return 0;
}

}  // namespace wish::fuzz
