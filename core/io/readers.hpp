#pragma once
// Internal to core/io: one reader per format. read_mesh (mesh_reader.cpp) has already checked the byte limit and
// chosen the format; each reader fills ReadResult::mesh, encoding and notes, and throws on the first problem.

#include <string_view>

#include "core/io/mesh_io.hpp"

namespace wish::io_detail {

ReadResult read_obj(std::string_view bytes, const ReadLimits& limits);
ReadResult read_off(std::string_view bytes, const ReadLimits& limits);
ReadResult read_ply(std::string_view bytes, const ReadLimits& limits);
// `binary`: from the size rule (84 + 50 n bytes) or, for a file that does not satisfy it, from its content.
ReadResult read_stl(std::string_view bytes, const ReadLimits& limits, bool binary);

// True when the bytes are a binary STL by the size rule: 80-byte header, uint32 n, then exactly 50 n bytes.
bool is_binary_stl_size(std::string_view bytes);
// True when the first `window` bytes contain a byte that never occurs in the text formats (NUL, most controls).
bool looks_binary(std::string_view bytes, std::size_t window = 4096);

}  // namespace wish::io_detail
