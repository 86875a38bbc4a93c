#pragma once
// Internal to core/io: collects what a reader parses into a Mesh, enforcing ReadLimits as it goes.
//
// Every reader goes through here, so the rules are the same for all formats:
//  * declared counts (headers) are checked against the limits *before* anything is reserved, and the reservation
//    is further bounded by what the remaining bytes could possibly hold (a 30-byte file claiming 10^9 vertices
//    reserves nothing big);
//  * coordinates must be finite; corner indices are 0-based and must name a vertex already read;
//  * polygons are fan-triangulated (v0, vi, vi+1); polygons with fewer than 3 corners are skipped and counted in a
//    note, never dropped silently.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/io/cursor.hpp"
#include "core/io/mesh_io.hpp"

namespace wish::io_detail {

class MeshBuilder {
 public:
  MeshBuilder(const ReadLimits& limits, MeshFormat format) : limits_(limits), format_(format) {}

  // `declared` from a header; `max_possible` = how many the remaining input could hold at the minimum record size.
  void expect_vertices(std::int64_t declared, std::int64_t max_possible);
  void expect_polygons(std::int64_t declared, std::int64_t max_possible);

  void add_vertex(double x, double y, double z, Location where);
  void add_polygon(std::span<const std::int64_t> corners, Location where);
  // Checks a polygon size before its corners are read (so a "1e9 corners" face is refused up front).
  void check_polygon_size(std::int64_t corners, Location where) const;

  std::int64_t vertex_count() const { return static_cast<std::int64_t>(coords_.size() / 3); }
  std::int64_t triangle_count() const { return static_cast<std::int64_t>(triangles_.size() / 3); }
  std::int64_t polygon_count() const { return polygons_; }

  // Builds the mesh (throws "empty_mesh" when there are no vertices or no triangles) and appends notes.
  Mesh finish(std::vector<std::string>& notes);

 private:
  ReadLimits limits_;
  MeshFormat format_;
  std::vector<double> coords_;   // x0 y0 z0 x1 ...
  std::vector<int> triangles_;   // a0 b0 c0 a1 ...
  std::int64_t polygons_ = 0;
  std::int64_t triangulated_polygons_ = 0;  // polygons with more than 3 corners
  std::int64_t skipped_polygons_ = 0;       // fewer than 3 corners
};

}  // namespace wish::io_detail
