#pragma once
// Reading and writing triangle meshes: OBJ, PLY (ascii / binary little / big endian), OFF, STL (ascii / binary).
// Readers work on memory buffers (uploads arrive as bytes); the file functions read the file then call them.
// Hostile input is expected: every limit is checked *before* allocating, nothing is read out of bounds, and the
// first problem is reported with its line (text) or byte offset (binary) in an InvalidInputError:
//   code "parse_error"        malformed content         details: line or byte_offset, format
//   code "index_out_of_range" face index not in [0, #V) details: face, index, vertex_count
//   code "non_finite_vertex"  NaN / Inf coordinate      details: vertex, line or byte_offset
//   code "empty_mesh"         no vertices or no faces
// a LimitExceededError (code "limit_exceeded", details: limit, value, allowed), or a WishError with category
// UnsupportedFormat (code "unsupported_format") when the content is none of the formats.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh/mesh.hpp"

namespace wish {

enum class MeshFormat { Unknown, Obj, Ply, Off, Stl };
enum class MeshEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

const char* to_string(MeshFormat format);
// "obj", "ply", "off", "stl" (case-insensitive, with or without a leading dot, or a MIME type such as
// "model/obj", "application/ply", "model/stl"); Unknown otherwise.
MeshFormat format_from_name(std::string_view name);

struct ReadLimits {
  std::uint64_t max_bytes = 512ull << 20;     // whole input size
  std::int64_t max_vertices = 2'000'000;      // declared or read
  std::int64_t max_faces = 4'000'000;         // triangles after fan triangulation
  std::int64_t max_line_length = 1 << 20;     // bytes in one text line
  std::int64_t max_polygon_vertices = 1024;   // corners of one polygon before triangulation
};

struct ReadOptions {
  ReadLimits limits;
  MeshFormat hint = MeshFormat::Unknown;  // from an extension or a Content-Type; content detection wins
};

struct ReadResult {
  Mesh mesh;
  MeshFormat format = MeshFormat::Unknown;
  MeshEncoding encoding = MeshEncoding::Ascii;
  // What the reader changed or ignored, one sentence each ("fan-triangulated 12 polygons into 24 triangles",
  // "welded 2,562 STL corners into 642 vertices"); nothing a user sent is dropped silently.
  std::vector<std::string> notes;
};

// Detects the format from the content (PLY magic, binary STL size equation, "solid", OFF header, OBJ
// statements); `hint` only breaks ties. Returns Unknown when nothing matches.
MeshFormat detect_format(std::string_view bytes, MeshFormat hint = MeshFormat::Unknown);

ReadResult read_mesh(std::string_view bytes, const ReadOptions& options = {});
ReadResult read_mesh_file(const std::filesystem::path& path, ReadOptions options = {});  // hint from extension

// Serialises a mesh. OBJ and OFF are ASCII only; PLY and STL take any encoding (STL: little endian binary).
std::string write_mesh(const Mesh& mesh, MeshFormat format, MeshEncoding encoding = MeshEncoding::Ascii);
void write_mesh_file(const Mesh& mesh, const std::filesystem::path& path,
                     MeshEncoding encoding = MeshEncoding::BinaryLittleEndian);  // format from extension

}  // namespace wish
