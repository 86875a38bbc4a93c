#include "core/io/mesh_builder.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

#include "core/common/errors.hpp"

namespace wish::io_detail {

namespace {

void add_location(ErrorDetails& details, Location where) {
  if (where.line > 0) details["line"] = where.line;
  if (where.byte_offset >= 0) details["byte_offset"] = where.byte_offset;
}

std::string describe(Location where) {
  if (where.line > 0) return "line " + std::to_string(where.line);
  if (where.byte_offset >= 0) return "byte " + std::to_string(where.byte_offset);
  return "input";
}

}  // namespace

void MeshBuilder::expect_vertices(std::int64_t declared, std::int64_t max_possible) {
  if (declared < 0) throw_parse_error(format_, {}, "negative vertex count " + std::to_string(declared) + " in the header");
  if (declared > limits_.max_vertices)
    throw_limit("max_vertices", declared, limits_.max_vertices, format_name(format_) + " header declares too many vertices");
  coords_.reserve(3 * static_cast<std::size_t>(std::clamp<std::int64_t>(std::min(declared, max_possible), 0, declared)));
}

void MeshBuilder::expect_polygons(std::int64_t declared, std::int64_t max_possible) {
  if (declared < 0) throw_parse_error(format_, {}, "negative face count " + std::to_string(declared) + " in the header");
  // Every polygon yields at least one triangle, so more polygons than allowed triangles can never fit.
  if (declared > limits_.max_faces)
    throw_limit("max_faces", declared, limits_.max_faces, format_name(format_) + " header declares too many faces");
  triangles_.reserve(3 * static_cast<std::size_t>(std::clamp<std::int64_t>(std::min(declared, max_possible), 0, declared)));
}

void MeshBuilder::add_vertex(double x, double y, double z, Location where) {
  const std::int64_t index = vertex_count();
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    ErrorDetails details{{"vertex", index}, {"format", std::string(to_string(format_))}};
    add_location(details, where);
    throw InvalidInputError("non_finite_vertex",
                            format_name(format_) + ", " + describe(where) + ": vertex " + std::to_string(index) +
                                " has a non-finite coordinate (NaN or Inf)",
                            std::move(details));
  }
  if (index >= limits_.max_vertices || index >= INT_MAX)
    throw_limit("max_vertices", index + 1, std::min<std::int64_t>(limits_.max_vertices, INT_MAX),
                format_name(format_) + ": too many vertices");
  coords_.insert(coords_.end(), {x, y, z});
}

void MeshBuilder::check_polygon_size(std::int64_t corners, Location where) const {
  if (corners < 0) throw_parse_error(format_, where, "negative corner count " + std::to_string(corners));
  if (corners > limits_.max_polygon_vertices)
    throw_limit("max_polygon_vertices", corners, limits_.max_polygon_vertices,
                format_name(format_) + ", " + describe(where) + ": polygon " + std::to_string(polygons_) + " has too many corners");
}

void MeshBuilder::add_polygon(std::span<const std::int64_t> corners, Location where) {
  const auto n = static_cast<std::int64_t>(corners.size());
  check_polygon_size(n, where);
  const std::int64_t face = polygons_++;
  for (const std::int64_t index : corners) {
    if (index < 0 || index >= vertex_count()) {
      ErrorDetails details{{"face", face}, {"index", index}, {"vertex_count", vertex_count()}, {"format", std::string(to_string(format_))}};
      add_location(details, where);
      throw InvalidInputError("index_out_of_range",
                              format_name(format_) + ", " + describe(where) + ": face " + std::to_string(face) +
                                  " refers to vertex " + std::to_string(index) + ", but only " +
                                  std::to_string(vertex_count()) + " vertices are defined (valid: 0.." +
                                  std::to_string(vertex_count() - 1) + ")",
                              std::move(details));
    }
  }
  if (n < 3) {
    ++skipped_polygons_;
    return;
  }
  if (triangle_count() + (n - 2) > limits_.max_faces)
    throw_limit("max_faces", triangle_count() + (n - 2), limits_.max_faces, format_name(format_) + ": too many triangles");
  if (n > 3) ++triangulated_polygons_;
  for (std::int64_t i = 1; i + 1 < n; ++i)
    triangles_.insert(triangles_.end(), {static_cast<int>(corners[0]), static_cast<int>(corners[i]), static_cast<int>(corners[i + 1])});
}

Mesh MeshBuilder::finish(std::vector<std::string>& notes) {
  if (vertex_count() == 0 || triangle_count() == 0)
    throw InvalidInputError("empty_mesh",
                            format_name(format_) + ": the file has " + with_commas(vertex_count()) + " vertices and " +
                                with_commas(triangle_count()) + " triangles; a surface mesh needs both",
                            {{"vertices", vertex_count()}, {"faces", triangle_count()}, {"format", std::string(to_string(format_))}});
  if (triangulated_polygons_ > 0)
    notes.push_back("fan-triangulated " + with_commas(triangulated_polygons_) + " polygons with more than 3 corners (" +
                    with_commas(polygons_ - skipped_polygons_) + " faces became " + with_commas(triangle_count()) + " triangles)");
  if (skipped_polygons_ > 0)
    notes.push_back("ignored " + with_commas(skipped_polygons_) + " faces with fewer than 3 corners");
  Mesh mesh;
  mesh.vertices.resize(vertex_count(), 3);
  for (Eigen::Index i = 0; i < mesh.vertices.rows(); ++i)
    for (int k = 0; k < 3; ++k) mesh.vertices(i, k) = coords_[3 * static_cast<std::size_t>(i) + k];
  mesh.faces.resize(triangle_count(), 3);
  for (Eigen::Index i = 0; i < mesh.faces.rows(); ++i)
    for (int k = 0; k < 3; ++k) mesh.faces(i, k) = triangles_[3 * static_cast<std::size_t>(i) + k];
  std::vector<double>().swap(coords_);
  std::vector<int>().swap(triangles_);
  return mesh;
}

}  // namespace wish::io_detail
