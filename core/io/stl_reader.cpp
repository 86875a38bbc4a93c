// STL, ASCII and binary. STL stores every triangle with its own three corners, so corners are welded into shared
// vertices by exact position (the only safe rule: no tolerance can be right for every unit). -0.0 and 0.0 are the
// same position. Facet normals are ignored: the orientation comes from the corner order, as everywhere in WISH.
//   binary: 80-byte header, uint32 n (little endian), n records of 12 float32 (normal, 3 corners) + uint16.
//   ASCII:  solid <name> / facet normal nx ny nz / outer loop / vertex x y z (3 or more) / endloop / endfacet /
//           endsolid; several solids in one file are read into one mesh.
#include <array>
#include <cstring>
#include <unordered_map>
#include <vector>

#include "core/io/cursor.hpp"
#include "core/io/mesh_builder.hpp"
#include "core/io/readers.hpp"

namespace wish::io_detail {

namespace {

using Key = std::array<std::uint64_t, 3>;

struct KeyHash {
  std::size_t operator()(const Key& k) const noexcept {
    std::uint64_t h = 1469598103934665603ull;
    for (const std::uint64_t v : k) h = (h ^ v) * 1099511628211ull ^ (v >> 29);
    return static_cast<std::size_t>(h);
  }
};

// Welds corners as they arrive; the builder sees each distinct position once, in order of first appearance.
class Welder {
 public:
  explicit Welder(MeshBuilder& builder) : builder_(builder) {}
  std::int64_t corner(double x, double y, double z, Location where) {
    ++corners_;
    const double p[3] = {x + 0.0, y + 0.0, z + 0.0};  // + 0.0 turns -0.0 into 0.0
    Key key;
    for (int k = 0; k < 3; ++k) std::memcpy(&key[static_cast<std::size_t>(k)], &p[k], sizeof(double));
    const auto [it, inserted] = index_.try_emplace(key, builder_.vertex_count());
    if (inserted) builder_.add_vertex(x, y, z, where);  // checks finiteness and the vertex limit
    return it->second;
  }
  std::int64_t corners() const { return corners_; }

 private:
  MeshBuilder& builder_;
  std::unordered_map<Key, std::int64_t, KeyHash> index_;
  std::int64_t corners_ = 0;
};

void read_binary(std::string_view bytes, MeshBuilder& builder, Welder& welder, std::vector<std::string>& notes) {
  ByteCursor cursor(bytes, MeshFormat::Stl);
  cursor.require(84, "a binary STL needs an 80-byte header and a triangle count");
  cursor.skip(80);
  const std::int64_t n = cursor.read<std::uint32_t>(false);
  builder.expect_polygons(n, static_cast<std::int64_t>(cursor.remaining() / 50));
  if (static_cast<std::uint64_t>(n) * 50 > cursor.remaining())
    cursor.fail("the header declares " + with_commas(n) + " triangles (" + std::to_string(84 + 50 * n) + " bytes) but the file has " +
                std::to_string(bytes.size()) + " bytes (truncated)");
  std::int64_t corners[3];
  for (std::int64_t t = 0; t < n; ++t) {
    const Location at = cursor.where();
    cursor.skip(12);  // facet normal
    for (auto& corner : corners) {
      const Location corner_at = cursor.where();
      const double x = cursor.read<float>(false), y = cursor.read<float>(false), z = cursor.read<float>(false);
      corner = welder.corner(x, y, z, corner_at);
    }
    cursor.skip(2);  // attribute byte count
    builder.add_polygon(corners, at);
  }
  if (cursor.remaining() > 0) notes.push_back("ignored " + with_commas(static_cast<std::int64_t>(cursor.remaining())) + " bytes after the last STL triangle");
}

void read_ascii(std::string_view bytes, const ReadLimits& limits, MeshBuilder& builder, Welder& welder) {
  LineCursor lines(bytes, MeshFormat::Stl, limits.max_line_length);
  std::vector<std::int64_t> loop;
  bool in_loop = false;
  std::string_view line, keyword, token;
  while (lines.next_content_line(line, '\0')) {
    Tokens tokens(line);
    tokens.next(keyword);
    if (keyword == "vertex") {
      if (!in_loop) lines.fail("\"vertex\" outside an \"outer loop\"");
      double xyz[3];
      for (double& c : xyz)
        if (!tokens.next(token) || !parse_double(token, c)) lines.fail("expected 3 vertex coordinates");
      builder.check_polygon_size(static_cast<std::int64_t>(loop.size()) + 1, lines.where());
      loop.push_back(welder.corner(xyz[0], xyz[1], xyz[2], lines.where()));
    } else if (keyword == "outer") {
      if (in_loop) lines.fail("\"outer loop\" inside another loop");
      in_loop = true;
      loop.clear();
    } else if (keyword == "endloop") {
      if (!in_loop) lines.fail("\"endloop\" without \"outer loop\"");
      in_loop = false;
      builder.add_polygon(loop, lines.where());
    } else if (keyword == "facet" || keyword == "endfacet" || keyword == "solid" || keyword == "endsolid") {
      if (in_loop) lines.fail("\"" + std::string(keyword) + "\" inside a loop (missing \"endloop\")");
    } else {
      lines.fail("unexpected \"" + std::string(keyword.substr(0, 40)) + "\" in an ASCII STL");
    }
  }
  if (in_loop) lines.fail("the file ends inside a facet (missing \"endloop\")");
}

}  // namespace

ReadResult read_stl(std::string_view bytes, const ReadLimits& limits, bool binary) {
  MeshBuilder builder(limits, MeshFormat::Stl);
  Welder welder(builder);
  ReadResult result;
  result.encoding = binary ? MeshEncoding::BinaryLittleEndian : MeshEncoding::Ascii;
  std::vector<std::string> notes;
  if (binary) read_binary(bytes, builder, welder, notes);
  else read_ascii(bytes, limits, builder, welder);
  result.mesh = builder.finish(result.notes);
  result.notes.push_back("welded " + with_commas(welder.corners()) + " STL corners into " + with_commas(result.mesh.vertex_count()) +
                         " vertices by exact position");
  result.notes.insert(result.notes.end(), notes.begin(), notes.end());
  return result;
}

}  // namespace wish::io_detail
