#pragma once
// Internal to core/validation: the combinatorial part of the mesh report, from the faces alone.
//
// Conventions: only "proper" faces take part — three distinct indices in [0, #V). Faces with a repeated or
// out-of-range index have no well-defined edges; the report counts them as degenerate instead.
//  * An undirected edge {a, b} is incident to every proper face that has a and b as consecutive corners.
//    1 face: boundary edge; more than 2: non-manifold edge; exactly 2 traversing it in the same direction
//    (a->b twice): an orientation conflict.
//  * Components: vertices connected through proper faces.
//  * Fans: around vertex v, the incident faces (v, x, y) linked when they share an edge (v, x); a manifold vertex
//    has exactly one fan. Counted as the connected components of the link graph {x - y}.

#include <cstdint>

#include <Eigen/Core>

namespace wish::validation_detail {

struct EdgeTopology {
  std::int64_t proper_faces = 0;
  std::int64_t referenced_vertices = 0;  // by proper faces
  std::int64_t edges = 0;
  std::int64_t boundary_edges = 0;
  std::int64_t nonmanifold_edges = 0;
  std::int64_t misoriented_edges = 0;    // two faces, same direction
  std::int64_t nonmanifold_vertices = 0;
  std::int64_t components = 0;
};

bool is_proper_face(const Eigen::MatrixX3i& faces, Eigen::Index f, Eigen::Index vertex_count);

EdgeTopology compute_edge_topology(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count);

}  // namespace wish::validation_detail
