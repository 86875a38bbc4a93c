// prepare_for_mapping: repairs the harmless defects (each reported as a RepairAction), re-analyses, and turns every
// remaining reason the mesh cannot be mapped into a ValidationIssue.
//
// Repair order matters: unreferenced vertices are dropped first so that welding counts only vertices in use; welding
// can turn zero-area faces into faces repeating a vertex, which the edge collapse right after it drops; welding can
// create duplicate faces, so duplicates are removed after it; orientation is judged last, on the final faces.
//
// Repair codes (RepairAction::code): dropped_unreferenced_vertices, welded_duplicate_vertices,
// collapsed_zero_length_edges, removed_duplicate_faces, flipped_orientation.
#include <algorithm>
#include <array>
#include <unordered_map>
#include <unordered_set>

#include "core/validation/mesh_report.hpp"
#include "core/validation/edge_topology.hpp"
#include "core/validation/position_key.hpp"

namespace wish {

namespace {

std::string count_text(std::int64_t n) {
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return n < 0 ? "-" + out : out;
}

std::string plural(std::int64_t n, const char* one, const char* many) { return count_text(n) + " " + (n == 1 ? one : many); }

// Keeps the vertices with keep[v] and renumbers the faces; returns how many were removed.
std::int64_t compact_vertices(Mesh& mesh, const std::vector<char>& keep) {
  std::vector<int> new_index(keep.size(), -1);
  int next = 0;
  for (std::size_t v = 0; v < keep.size(); ++v)
    if (keep[v]) new_index[v] = next++;
  const auto removed = static_cast<std::int64_t>(keep.size()) - next;
  if (removed == 0) return 0;
  Eigen::MatrixX3d vertices(next, 3);
  for (std::size_t v = 0; v < keep.size(); ++v)
    if (keep[v]) vertices.row(new_index[v]) = mesh.vertices.row(static_cast<Eigen::Index>(v));
  mesh.vertices = std::move(vertices);
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) mesh.faces(f, k) = new_index[static_cast<std::size_t>(mesh.faces(f, k))];
  return removed;
}

bool indices_in_range(const Mesh& mesh) {
  return mesh.face_count() == 0 || (mesh.faces.minCoeff() >= 0 && mesh.faces.maxCoeff() < mesh.vertex_count());
}

std::int64_t drop_unreferenced(Mesh& mesh) {
  std::vector<char> used(static_cast<std::size_t>(mesh.vertex_count()), 0);
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(mesh.faces(f, k))] = 1;
  return compact_vertices(mesh, used);
}

std::int64_t weld_duplicates(Mesh& mesh) {
  std::unordered_map<validation_detail::PositionKey, int, validation_detail::PositionHash> first;
  first.reserve(static_cast<std::size_t>(mesh.vertex_count()));
  std::vector<int> target(static_cast<std::size_t>(mesh.vertex_count()));
  std::vector<char> keep(target.size(), 1);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
    const auto [it, inserted] = first.try_emplace(validation_detail::position_key(mesh.vertices, v), static_cast<int>(v));
    target[static_cast<std::size_t>(v)] = it->second;
    if (!inserted) keep[static_cast<std::size_t>(v)] = 0;
  }
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) mesh.faces(f, k) = target[static_cast<std::size_t>(mesh.faces(f, k))];
  return compact_vertices(mesh, keep);
}

// Welding keeps the face rows, so face f of `welded` is face f of `original` with welded corners. A face whose corners
// were distinct and now repeat one had two corners at exactly the same position: zero area, and a zero-length edge
// between them (the twin vertex of real segmentations: a vertex duplicated at its neighbour's position, with the two
// zero-area faces that the twin makes). Dropping those faces completes the collapse of that edge.
struct EdgeCollapse {
  std::int64_t edges = 0;  // distinct zero-length edges (p, q) of the input that welding collapsed
  std::int64_t faces = 0;  // faces dropped
};

EdgeCollapse drop_faces_made_degenerate(const Mesh& original, Mesh& welded) {
  EdgeCollapse out;
  std::unordered_set<std::array<int, 3>, validation_detail::TripleHash> collapsed_edges;
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(welded.face_count()));
  const Eigen::Index nv = original.vertex_count();
  for (Eigen::Index f = 0; f < welded.face_count(); ++f) {
    const bool was_proper = validation_detail::is_proper_face(original.faces, f, nv);
    const bool is_proper = validation_detail::is_proper_face(welded.faces, f, welded.vertex_count());
    if (!was_proper || is_proper) {
      kept.push_back(f);
      continue;
    }
    ++out.faces;
    for (int k = 0; k < 3; ++k) {
      const int l = (k + 1) % 3;
      if (welded.faces(f, k) != welded.faces(f, l)) continue;
      const int p = original.faces(f, k), q = original.faces(f, l);
      collapsed_edges.insert({std::min(p, q), std::max(p, q), 0});
    }
  }
  out.edges = static_cast<std::int64_t>(collapsed_edges.size());
  if (out.faces > 0) {
    Eigen::MatrixX3i faces(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t i = 0; i < kept.size(); ++i) faces.row(static_cast<Eigen::Index>(i)) = welded.faces.row(kept[i]);
    welded.faces = std::move(faces);
  }
  return out;
}

bool closed_manifold_connected(const MeshReport& r) {
  return r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.nonmanifold_vertices == 0 && r.components == 1;
}

// Faces that already repeat a vertex as read: an STL file has no vertex identity, so its reader welds corners by
// position and a twin vertex arrives welded, its two zero-area faces as faces (v, v, a). Drops them; `edges` counts
// the distinct repeated vertices (one per collapsed edge of a twin).
EdgeCollapse drop_faces_repeating_a_vertex(Mesh& mesh) {
  EdgeCollapse out;
  std::unordered_set<int> repeated;
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(mesh.face_count()));
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    const int a = mesh.faces(f, 0), b = mesh.faces(f, 1), c = mesh.faces(f, 2);
    if (a != b && b != c && c != a) {
      kept.push_back(f);
      continue;
    }
    ++out.faces;
    repeated.insert(a == b || a == c ? a : b);
  }
  out.edges = static_cast<std::int64_t>(repeated.size());
  if (out.faces > 0) {
    Eigen::MatrixX3i faces(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t i = 0; i < kept.size(); ++i) faces.row(static_cast<Eigen::Index>(i)) = mesh.faces.row(kept[i]);
    mesh.faces = std::move(faces);
  }
  return out;
}

// Removes faces equal to an earlier one up to rotation (a b c ~ b c a). Opposite copies (a c b) are not harmless
// duplicates but a two-sided sheet; they stay and show up as non-manifold edges.
std::int64_t remove_duplicate_faces(Mesh& mesh) {
  std::unordered_set<std::array<int, 3>, validation_detail::TripleHash> seen;
  seen.reserve(static_cast<std::size_t>(mesh.face_count()));
  std::vector<Eigen::Index> kept;
  kept.reserve(static_cast<std::size_t>(mesh.face_count()));
  for (Eigen::Index f = 0; f < mesh.face_count(); ++f) {
    std::array<int, 3> key{mesh.faces(f, 0), mesh.faces(f, 1), mesh.faces(f, 2)};
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    if (seen.insert(key).second) kept.push_back(f);
  }
  const auto removed = mesh.face_count() - static_cast<Eigen::Index>(kept.size());
  if (removed > 0) {
    Eigen::MatrixX3i faces(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t i = 0; i < kept.size(); ++i) faces.row(static_cast<Eigen::Index>(i)) = mesh.faces.row(kept[i]);
    mesh.faces = std::move(faces);
  }
  return removed;
}

std::vector<ValidationIssue> find_issues(const MeshReport& r) {
  std::vector<ValidationIssue> issues;
  const auto add = [&](const char* code, std::string message, ErrorDetails details) {
    issues.push_back({code, std::move(message), std::move(details)});
  };
  if (r.faces < 4)
    add("too_small", plural(r.faces, "face", "faces") + ": a closed surface needs at least 4 (a tetrahedron)", {{"faces", r.faces}});
  if (r.components > 1)
    add("multiple_components", plural(r.components, "connected component", "connected components") + ": a sphere map needs exactly one",
        {{"components", r.components}});
  if (r.boundary_edges > 0)
    add("not_closed", plural(r.boundary_edges, "boundary edge", "boundary edges") + ": the surface is open (it has holes); only closed surfaces map to a sphere",
        {{"boundary_edges", r.boundary_edges}});
  if (r.nonmanifold_edges > 0)
    add("non_manifold_edge", plural(r.nonmanifold_edges, "edge is", "edges are") + " shared by more than two faces (non-manifold)",
        {{"nonmanifold_edges", r.nonmanifold_edges}});
  if (r.nonmanifold_vertices > 0)
    add("non_manifold_vertex", plural(r.nonmanifold_vertices, "vertex joins", "vertices join") + " separate fans of faces (non-manifold)",
        {{"nonmanifold_vertices", r.nonmanifold_vertices}});
  if (!r.orientation_consistent)
    add("inconsistent_orientation",
        "faces are not consistently oriented: " + plural(r.misoriented_edges, "edge is", "edges are") + " traversed twice in the same direction",
        {{"misoriented_edges", r.misoriented_edges}});
  // Zero-area faces are geometry, which the map survives (mollified operators); a face repeating a vertex is not.
  if (const std::int64_t repeated = r.degenerate_faces - r.zero_area_faces; repeated > 0)
    add("degenerate_faces", plural(repeated, "degenerate face repeats", "degenerate faces repeat") + " a vertex",
        {{"degenerate_faces", repeated}});
  if (r.genus && *r.genus > 0)
    add("genus_nonzero",
        "genus " + count_text(*r.genus) + " (Euler characteristic " + count_text(r.euler_characteristic) + "): only genus-0 surfaces map to a sphere",
        {{"genus", *r.genus}, {"euler_characteristic", r.euler_characteristic}});
  return issues;
}

}  // namespace

PreparedMesh prepare_for_mapping(Mesh mesh, const RepairOptions& options) {
  PreparedMesh out;
  out.input_report = analyze_mesh(mesh);
  // Every repair that changes the mesh records itself, so while none has, the input's report is the mesh's: a clean
  // mesh is analysed once, not three times (the analysis sorts every half-edge and hashes every face and position:
  // 7 ms of a 10.8K-vertex nucleus's 0.03 s preparation each).
  const auto current_report = [&] { return out.repairs.empty() ? out.input_report : analyze_mesh(mesh); };
  // Repairs renumber vertices, which needs valid indices; a mesh with bad indices is only analysed.
  if (indices_in_range(mesh)) {
    if (options.drop_unreferenced_vertices)
      if (const auto n = drop_unreferenced(mesh); n > 0)
        out.repairs.push_back({"dropped_unreferenced_vertices", "dropped " + plural(n, "vertex", "vertices") + " not used by any face", n});
    if (options.weld_duplicate_vertices) {
      // Coincident vertices are not always a defect: a closed surface may touch itself at a point or along an
      // edge (cow.off, diplodocus.off). Welding is kept only when it does not make the surface non-manifold.
      Mesh welded = mesh;
      if (const auto n = weld_duplicates(welded); n > 0) {
        const MeshReport before = current_report(), after = analyze_mesh(welded);
        if (after.nonmanifold_edges <= before.nonmanifold_edges && after.nonmanifold_vertices <= before.nonmanifold_vertices) {
          // Welding a twin vertex turns its zero-area faces into faces repeating a vertex; dropping them collapses
          // the zero-length edge. The collapse is kept only when the surface stays closed, manifold, connected
          // and (when the input was already such a surface, i.e. welding did not close seams) keeps its Euler
          // characteristic — the collapse changed no topology. Otherwise the input is kept unwelded when it is
          // such a surface by itself (its zero-area faces are accepted), else welded as before and refused for the
          // faces repeating a vertex.
          EdgeCollapse collapse = drop_faces_made_degenerate(mesh, welded);
          bool weld = true;
          if (collapse.faces > 0) {
            const MeshReport collapsed = analyze_mesh(welded);
            const bool input_closed = closed_manifold_connected(before);
            const bool safe = closed_manifold_connected(collapsed) && collapsed.unreferenced_vertices == 0 &&
                              (!input_closed || collapsed.euler_characteristic == before.euler_characteristic);
            if (!safe) {
              weld = !input_closed;
              welded = mesh;
              weld_duplicates(welded);  // as before the collapse: the faces repeating a vertex stay and are refused
              collapse = {};
            }
          }
          if (weld) {
            mesh = std::move(welded);
            out.repairs.push_back({"welded_duplicate_vertices", "welded " + plural(n, "vertex", "vertices") + " into earlier vertices at exactly the same position", n});
            if (collapse.faces > 0)
              out.repairs.push_back({"collapsed_zero_length_edges",
                                     "collapsed " + plural(collapse.edges, "zero-length edge", "zero-length edges") + " between welded vertices by dropping the " +
                                         plural(collapse.faces, "zero-area face", "zero-area faces") + " that welding turned into faces repeating a vertex",
                                     collapse.edges});
          }
        }
      }
    }
    if (options.weld_duplicate_vertices) {
      // Faces that repeated a vertex as read (STL: welded by the reader) are the same zero-area faces of a welded
      // twin; they are dropped when the rest is a closed, manifold, connected surface using every vertex. No Euler
      // baseline exists here (the input's faces already were welded), and none is needed: validation judges the
      // surface without them either way — dropping them only removes a face that has no area and no edges.
      Mesh collapsed = mesh;
      if (const EdgeCollapse c = drop_faces_repeating_a_vertex(collapsed); c.faces > 0) {
        const MeshReport r = analyze_mesh(collapsed);
        if (closed_manifold_connected(r) && r.unreferenced_vertices == 0) {
          mesh = std::move(collapsed);
          out.repairs.push_back({"collapsed_zero_length_edges",
                                 "dropped " + plural(c.faces, "face", "faces") + " repeating a vertex (welded as read: " +
                                     plural(c.edges, "collapsed zero-length edge", "collapsed zero-length edges") + ")",
                                 c.edges});
        }
      }
    }
    if (options.remove_duplicate_faces)
      if (const auto n = remove_duplicate_faces(mesh); n > 0)
        out.repairs.push_back({"removed_duplicate_faces", "removed " + plural(n, "face", "faces") + " repeating an earlier face", n});
    if (options.orient_outward) {
      const MeshReport r = current_report();
      // Only a closed, connected, consistently oriented surface has an inside; flipping anything else means nothing.
      if (r.orientation_consistent && r.boundary_edges == 0 && r.nonmanifold_edges == 0 && r.components == 1 && r.signed_volume < 0) {
        mesh.faces.col(1).swap(mesh.faces.col(2));
        out.repairs.push_back({"flipped_orientation",
                               "flipped all " + count_text(mesh.face_count()) + " faces: they were oriented inward (signed volume " +
                                   std::to_string(r.signed_volume) + ")",
                               mesh.face_count()});
      }
    }
  }
  out.report = current_report();
  out.issues = find_issues(out.report);
  out.mesh = std::move(mesh);
  return out;
}

void require_mappable(const PreparedMesh& prepared) {
  if (prepared.mappable()) return;
  const ValidationIssue& first = prepared.issues.front();
  throw WishError(ErrorCategory::Unmappable, first.code, first.message, first.details);
}

}  // namespace wish
