#pragma once
// Topology and geometry report of a triangle mesh, and the check that it can be mapped to the sphere:
// one component, closed, edge- and vertex-manifold, consistently oriented, genus 0.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/common/errors.hpp"
#include "core/mesh/mesh.hpp"

namespace wish {

struct MeshReport {
  std::int64_t vertices = 0, edges = 0, faces = 0;
  std::int64_t components = 0;            // connected through faces
  std::int64_t boundary_edges = 0;        // edges with exactly one incident face
  std::int64_t nonmanifold_edges = 0;     // edges with more than two incident faces
  std::int64_t nonmanifold_vertices = 0;  // vertices whose incident faces form more than one fan
  std::int64_t euler_characteristic = 0;  // V - E + F (referenced vertices only)
  std::optional<std::int64_t> genus;      // (2 - chi) / 2 for a closed, connected, manifold mesh; else none
  std::int64_t degenerate_faces = 0;      // repeated index or zero area
  // Added: of those, faces with three distinct vertices and exactly zero area (e.g. a vertex duplicated at its
  // twin's position). They do not make a mesh unmappable: the map's operators mollify them (reported with the map).
  std::int64_t zero_area_faces = 0;
  std::int64_t duplicate_faces = 0;       // same vertex set as an earlier face
  std::int64_t unreferenced_vertices = 0;
  std::int64_t duplicate_vertices = 0;    // exactly equal positions
  bool orientation_consistent = true;     // every interior edge traversed once in each direction
  std::int64_t misoriented_edges = 0;     // edges with two faces that traverse them in the same direction
  double signed_volume = 0;               // (1/6) sum x0 . (x1 x x2); > 0 for outward orientation
  double area = 0;
  std::array<double, 3> bbox_min{}, bbox_max{};
  bool operator==(const MeshReport&) const = default;  // every field, one added later included
};

// One reason a mesh cannot be mapped; `code` is machine-readable ("genus_nonzero", "not_closed",
// "multiple_components", "non_manifold_edge", "non_manifold_vertex", "inconsistent_orientation",
// "degenerate_faces" (a face repeating a vertex; zero-area faces are accepted), "too_small"), `message` a sentence
// with numbers.
struct ValidationIssue {
  std::string code;
  std::string message;
  ErrorDetails details;
};

// A harmless defect that was repaired (never silently): "dropped_unreferenced_vertices",
// "welded_duplicate_vertices", "collapsed_zero_length_edges" (faces that welding turned into faces repeating a
// vertex were zero-area faces on a zero-length edge; dropping them collapses the edge, kept only when the surface
// stays closed, manifold, connected, with the same Euler characteristic; `count` = edges), "removed_duplicate_faces",
// "flipped_orientation".
struct RepairAction {
  std::string code;
  std::string message;
  std::int64_t count = 0;
};

MeshReport analyze_mesh(const Mesh& mesh);

struct PreparedMesh {
  Mesh mesh;                            // repaired mesh, ready for mapping when `issues` is empty
  MeshReport input_report;              // of the mesh as read
  MeshReport report;                    // of `mesh` after repairs
  std::vector<RepairAction> repairs;
  std::vector<ValidationIssue> issues;  // empty <=> mappable
  bool mappable() const { return issues.empty(); }
};

struct RepairOptions {
  bool drop_unreferenced_vertices = true;
  bool weld_duplicate_vertices = true;   // exact position equality only; collapses the zero-length edges it makes
  bool orient_outward = true;            // flip all faces when the signed volume is negative
  bool remove_duplicate_faces = true;    // a face equal to an earlier one up to rotation (same orientation)
};

// Repairs harmless defects, re-analyses, and lists every reason the mesh cannot be mapped.
PreparedMesh prepare_for_mapping(Mesh mesh, const RepairOptions& options = {});

// Throws WishError(ErrorCategory::Unmappable, first issue's code, message, details) unless mappable.
void require_mappable(const PreparedMesh& prepared);

}  // namespace wish
