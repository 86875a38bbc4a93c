#include "core/spherical_map/progressive_embedding.hpp"
#include "core/spherical_map/mobius.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/common/stage_profile.hpp"


namespace wish::spherical {
namespace {

using Clock = std::chrono::steady_clock;

void erase_one(std::vector<int>& list, int value) {
  const auto it = std::find(list.begin(), list.end(), value);
  if (it != list.end()) {
    *it = list.back();
    list.pop_back();
  }
}

// The mesh under half-edge collapses and their undo (vertex splits). Faces keep their input index and cyclic
// order; a collapse v → u writes u where v was and drops the two faces that contained both.
class ProgressiveMesh {
 public:
  struct Collapse {
    int removed = 0, kept = 0;
    std::vector<std::pair<int, int>> moved;  // (face, corner) where `removed` was replaced by `kept`
    std::vector<int> killed;                 // the faces that contained both
  };

  ProgressiveMesh(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count)
      : faces_(faces), face_alive_(static_cast<size_t>(faces.rows()), 1),
        vertex_alive_(static_cast<size_t>(vertex_count), 1), vertex_faces_(static_cast<size_t>(vertex_count)) {
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) vertex_faces_[static_cast<size_t>(faces(f, k))].push_back(static_cast<int>(f));
  }

  const Eigen::MatrixX3i& faces() const { return faces_; }
  bool face_alive(int f) const { return face_alive_[static_cast<size_t>(f)] != 0; }
  bool vertex_alive(int v) const { return vertex_alive_[static_cast<size_t>(v)] != 0; }
  const std::vector<int>& faces_of(int v) const { return vertex_faces_[static_cast<size_t>(v)]; }

  std::vector<int> neighbours(int v) const {
    std::vector<int> n;
    for (int f : faces_of(v))
      for (int k = 0; k < 3; ++k)
        if (faces_(f, k) != v) n.push_back(faces_(f, k));
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  }

  // Link condition for the edge uv of a closed manifold: exactly the two opposite vertices are common neighbours
  // (a third one would make the collapse pinch the surface along a separating triangle).
  bool link_condition(int u, int v) const {
    const std::vector<int> nu = neighbours(u), nv = neighbours(v);
    std::vector<int> common;
    std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
    return common.size() == 2;
  }

  Collapse collapse(int removed, int kept) {
    Collapse c;
    c.removed = removed;
    c.kept = kept;
    for (int f : std::vector<int>(faces_of(removed))) {
      const bool has_kept = faces_(f, 0) == kept || faces_(f, 1) == kept || faces_(f, 2) == kept;
      if (has_kept) {
        face_alive_[static_cast<size_t>(f)] = 0;
        for (int k = 0; k < 3; ++k)
          if (faces_(f, k) != removed) erase_one(vertex_faces_[static_cast<size_t>(faces_(f, k))], f);
        c.killed.push_back(f);
      } else {
        for (int k = 0; k < 3; ++k)
          if (faces_(f, k) == removed) {
            faces_(f, k) = kept;
            c.moved.emplace_back(f, k);
          }
        vertex_faces_[static_cast<size_t>(kept)].push_back(f);
      }
    }
    vertex_faces_[static_cast<size_t>(removed)].clear();
    vertex_alive_[static_cast<size_t>(removed)] = 0;
    return c;
  }

  void split(const Collapse& c) {
    vertex_alive_[static_cast<size_t>(c.removed)] = 1;
    for (const auto& [f, k] : c.moved) {
      faces_(f, k) = c.removed;
      erase_one(vertex_faces_[static_cast<size_t>(c.kept)], f);
      vertex_faces_[static_cast<size_t>(c.removed)].push_back(f);
    }
    for (int f : c.killed) {
      face_alive_[static_cast<size_t>(f)] = 1;
      for (int k = 0; k < 3; ++k) vertex_faces_[static_cast<size_t>(faces_(f, k))].push_back(f);
    }
  }

 private:
  Eigen::MatrixX3i faces_;
  std::vector<char> face_alive_, vertex_alive_;
  std::vector<std::vector<int>> vertex_faces_;
};

// Shortest edge first (input lengths; a half-edge collapse moves no vertex, so an edge's length never changes),
// removing the endpoint of smaller degree. False when no edge passes the link condition above 4 vertices (not
// expected for a closed genus-0 manifold).
bool simplify_to_tetrahedron(ProgressiveMesh& mesh, const Eigen::MatrixX3d& x, std::vector<ProgressiveMesh::Collapse>& out) {
  const auto key = [&](int a, int b) { return (x.row(a) - x.row(b)).norm(); };
  using Entry = std::tuple<double, int, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const auto push_edges_of_faces = [&] {
    for (Eigen::Index f = 0; f < mesh.faces().rows(); ++f) {
      if (!mesh.face_alive(static_cast<int>(f))) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.faces()(f, k), b = mesh.faces()(f, (k + 1) % 3);
        if (a < b) queue.emplace(key(a, b), a, b);
      }
    }
  };
  push_edges_of_faces();
  Eigen::Index alive = x.rows();
  bool progress = true;
  while (alive > 4) {
    if (queue.empty()) {
      if (!progress) return false;
      progress = false;
      push_edges_of_faces();  // edges refused earlier may pass now that their neighbourhood changed
      continue;
    }
    const auto [length, a, b] = queue.top();
    queue.pop();
    if (!mesh.vertex_alive(a) || !mesh.vertex_alive(b)) continue;
    const std::vector<int> na = mesh.neighbours(a);
    if (!std::binary_search(na.begin(), na.end(), b)) continue;
    if (!mesh.link_condition(a, b)) continue;
    const bool remove_a = mesh.faces_of(a).size() < mesh.faces_of(b).size();
    const int removed = remove_a ? a : b, kept = remove_a ? b : a;
    out.push_back(mesh.collapse(removed, kept));
    --alive;
    progress = true;
    for (int w : mesh.neighbours(kept)) queue.emplace(key(kept, w), std::min(kept, w), std::max(kept, w));
  }
  return true;
}

// |a − b|, its squares summed as x² + (y² + z²): the order in which Eigen sums a row of a column-major matrix,
// where the positions were kept when the placements and step bounds below were measured (the maps stay
// bit-identical; Eigen sums a contiguous 3-vector as (x² + y²) + z²).
double distance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = a - b;
  return std::sqrt(d.x() * d.x() + (d.y() * d.y() + d.z() * d.z()));
}

// The sphere positions, the tests every move must pass, and the stretch energy the moves lower.
//
// Energy (Praun & Hoppe 2003 §3.2, after Sander, Snyder, Gortler, Hoppe 2001, "Texture mapping progressive
// meshes", §3): the L2 stretch of the map sphere → surface, Σ_f A_f · L2²(f), with A_f the area of the surface
// triangle and L2²(f) = (Γ² + γ²)/2 the mean squared singular value of the affine map from the sphere's chord
// triangle to it. With the cotangent formula of the Dirichlet energy, L2²(f) = Σ_k cot θ_k · |X_i − X_j|² / (4 a_f)
// (θ_k the chord triangle's angles, a_f its area, X the surface), so E_f = A_f · Σ_k (d_k / 2a_f) |X_i − X_j|² /
// (4 a_f) with d_k the dot product of the chord edges at corner k. For a similar triangle E_f = A_f² / a_f: the
// energy grows without bound as a sphere triangle shrinks relative to its surface triangle (a barrier against the
// exponential compression of thin parts that conformal and uniform-Tutte maps show), and its minimum under
// Σ a_f = 4π gives every face a sphere area proportional to its surface area.
class SphereEmbedding {
 public:
  SphereEmbedding(const ProgressiveMesh& mesh, const Eigen::MatrixX3d& surface, double min_height)
      : mesh_(mesh), x_(surface), u_(static_cast<size_t>(surface.rows()), Eigen::Vector3d::Zero()),
        terms_(static_cast<size_t>(mesh.faces().rows())), min_height_(min_height) {
    // A floor for the surface area of a face: zero-area input faces keep a (weak) barrier.
    double total = 0;
    for (Eigen::Index f = 0; f < mesh.faces().rows(); ++f)
      total += 0.5 * (x_.row(mesh.faces()(f, 1)) - x_.row(mesh.faces()(f, 0)))
                         .cross(x_.row(mesh.faces()(f, 2)) - x_.row(mesh.faces()(f, 0)))
                         .norm();
    area_floor_ = 1e-6 * total / static_cast<double>(std::max<Eigen::Index>(1, mesh.faces().rows()));
    for (Eigen::Index f = 0; f < mesh.faces().rows(); ++f) refresh_terms(static_cast<int>(f));
  }

  const Eigen::Vector3d& position(int v) const { return u_[static_cast<size_t>(v)]; }
  void set_position(int v, const Eigen::Vector3d& y) { u_[static_cast<size_t>(v)] = y; }
  // The positions as a V×3 matrix (the map).
  Eigen::MatrixX3d positions() const {
    Eigen::MatrixX3d m(static_cast<Eigen::Index>(u_.size()), 3);
    for (size_t i = 0; i < u_.size(); ++i) m.row(static_cast<Eigen::Index>(i)) = u_[i].transpose();
    return m;
  }
  // After a split or collapse that changed w's faces: their surface terms follow their new corners.
  void star_changed(int w) {
    for (int f : mesh_.faces_of(w)) refresh_terms(f);
  }

  // Smallest chord-triangle height of v's faces with v at y; −1 when one of them is not positively oriented.
  double star_score(int v, const Eigen::Vector3d& y) const {
    double worst = std::numeric_limits<double>::infinity();
    for (int f : mesh_.faces_of(v)) {
      Eigen::Vector3d p[3];
      corners(f, v, y, p);
      const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
      if (!(n.dot(p[0] + p[1] + p[2]) > 0)) return -1;
      // One square root for the longest edge (a correctly rounded sqrt is monotone: the same value as the
      // largest of the three edge lengths).
      const double longest =
          std::sqrt(std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()}));
      worst = std::min(worst, n.norm() / longest);
    }
    return worst;
  }
  bool valid(int v, const Eigen::Vector3d& y) const { return star_score(v, y) >= min_height_; }

  // The stretch energy of v's faces with v at y (see the class comment); +inf when a face is not positively
  // oriented or its height is below min_height (a move there is never taken).
  double star_energy(int v, const Eigen::Vector3d& y, double floor) const {
    double e = 0;
    for (int f : mesh_.faces_of(v)) {
      Eigen::Vector3d p[3];
      corners(f, v, y, p);
      const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
      const double twice_area = n.norm();
      if (!(n.dot(p[0] + p[1] + p[2]) > 0)) return std::numeric_limits<double>::infinity();
      const double longest = std::max({(p[1] - p[0]).squaredNorm(), (p[2] - p[1]).squaredNorm(), (p[0] - p[2]).squaredNorm()});
      if (twice_area < floor * std::sqrt(longest)) return std::numeric_limits<double>::infinity();
      e += stretch_of(f, p, twice_area);
    }
    return e;
  }

  // One descent move of v on its star's stretch energy: the gradient in v's tangent plane by central differences,
  // then a backtracking line search that takes the first shortened step which lowers the energy (so every accepted
  // position keeps all of v's faces positively oriented with height ≥ min_height). Returns the energy decrease.
  double optimise(int v) {
    const Eigen::Vector3d x = position(v);
    // The height floor of a move: min_height, or the star's present smallest height if a placement had to go
    // below it (a move may then not make it worse; it lets such a neighbourhood heal).
    const double floor = std::min(min_height_, std::max(0.0, star_score(v, x)));
    const double e0 = star_energy(v, x, floor);
    if (!std::isfinite(e0)) return 0;  // (not expected: every accepted state is valid)
    double reach = std::numeric_limits<double>::infinity();
    for (int f : mesh_.faces_of(v))
      for (int k = 0; k < 3; ++k)
        if (mesh_.faces()(f, k) != v) reach = std::min(reach, distance(position(mesh_.faces()(f, k)), x));
    if (!(reach > 0) || !std::isfinite(reach)) return 0;
    const Eigen::Vector3d helper = std::abs(x.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = helper.cross(x).normalized(), e2 = x.cross(e1);
    // The difference step shrinks until all four probes stay valid (a vertex next to the barrier — the one whose
    // nearly degenerate face most needs the move — would otherwise never move).
    const auto at = [&](const Eigen::Vector3d& d) { return star_energy(v, (x + d).normalized(), floor); };
    double g1 = 0, g2 = 0;
    bool finite = false;
    for (double h = 1e-3 * reach; h > 1e-9 * reach && !finite; h *= 0.1) {
      g1 = at(h * e1) - at(-h * e1);
      g2 = at(h * e2) - at(-h * e2);
      finite = std::isfinite(g1) && std::isfinite(g2);
    }
    if (!finite || (g1 == 0 && g2 == 0)) return 0;
    const Eigen::Vector3d direction = -(g1 * e1 + g2 * e2).normalized();
    for (double t = 0.5 * reach; t > 1e-6 * reach; t *= 0.5) {
      const Eigen::Vector3d y = (x + t * direction).normalized();
      const double e = star_energy(v, y, floor);
      if (e < e0) {
        set_position(v, y);
        return e0 - e;
      }
    }
    return 0;
  }

  // Re-inserts v (just split off u) inside the kernel of its one-ring. The kernel is computed exactly as a convex
  // polygon in the gnomonic chart about u's position p (central projection onto the tangent plane at p maps great
  // circles to straight lines, so "v left of the link edge (a, b)", det(y, a, b) > 0, is the half-plane
  // (p + s e1 + t e2)·(a × b) > 0 in the chart coordinates (s, t)): a square about p is clipped by one half-plane
  // per face of v's star (Sutherland & Hodgman 1974), and v goes to the clipped polygon's centroid, strictly inside
  // it whenever the polygon has area. The kernel is never empty in exact arithmetic (Praun & Hoppe's argument: the
  // sector that v's faces took from u's star reaches p, and every other link edge (a, b) of v bounded the valid
  // face (u, a, b)), so a centroid whose smallest face height is below `min_height` means a kernel too thin for
  // double precision: false, and the caller spreads the neighbourhood and tries again. Then u and v each move to
  // the centroid of their own kernel when that opens their thinnest face, and down the stretch energy.
  bool place(int v, int u, double min_height) {
    const std::optional<Eigen::Vector3d> y = kernel_centroid(v, position(u));
    if (!y || !(star_score(v, *y) >= min_height)) return false;
    set_position(v, *y);
    // The kernel is a wedge with its apex at u when v's faces took a thin sector of u's star: u moves to the
    // centroid of its own kernel, then v again, so neither stays at the other's apex.
    for (int round = 0; round < 2; ++round)
      for (int w : {u, v}) centre(w);
    for (int round = 0; round < 2; ++round) {
      optimise(v);
      optimise(u);
    }
    return true;
  }

  // Re-inserts v (just split off u) together with u inside the kernel K of u's star BEFORE the split (the polygon
  // P of u's old link; c is K's centroid): any point of K sees every edge of P, so u and v both in K leave every
  // face of the star with one corner on P positively oriented, and only the two faces (u, v, a), (v, u, b) that the
  // split restored (a, b: `apexes`) depend on how u and v sit: they are placed on the line through c that bisects
  // the angle a c b (it separates a and b), at ± s from c. Every face is then positively oriented and P is tiled
  // once (a triangulated disk with a simple boundary and no inverted face is embedded). Unlike v in its own kernel
  // — a wedge with apex at u when v's faces took a thin sector of u's star, where the two restored faces are
  // slivers with an area many orders below their surface share (measured on the 3-turn coil: sphere areas 1e-7
  // against a surface share 1e-1 at 72 vertices, which no later single-vertex move undid) — this splits u's
  // region between u and v. Of the offsets s that pass the height margin, the one of lowest stretch energy of the
  // two stars is kept; false (positions unchanged) when none passes.
  bool place_pair(int v, int u, const Eigen::Vector3d& c, const std::vector<int>& apexes, double min_height) {
    if (apexes.size() != 2) return false;
    const Eigen::Vector3d a = position(apexes[0]), b = position(apexes[1]);
    const auto tangent = [&](const Eigen::Vector3d& x) { return (x - x.dot(c) * c).normalized(); };
    Eigen::Vector3d w = tangent(a) + tangent(b);
    if (!(w.norm() > 1e-3)) w = c.cross(tangent(a));
    w.normalize();
    if (!w.allFinite()) return false;
    double reach = std::numeric_limits<double>::infinity();
    for (int x : {u, v})
      for (int f : mesh_.faces_of(x))
        for (int k = 0; k < 3; ++k) {
          const int y = mesh_.faces()(f, k);
          if (y != u && y != v) reach = std::min(reach, distance(position(y), c));
        }
    if (!(reach > 0) || !std::isfinite(reach)) return false;
    const Eigen::Vector3d saved_u = position(u), saved_v = position(v);
    Eigen::Vector3d best_u = saved_u, best_v = saved_v;
    double best = std::numeric_limits<double>::infinity();
    for (double s = 0.4 * reach; s > 1e-4 * reach; s *= 0.5)
      for (double sign : {1.0, -1.0}) {
        const Eigen::Vector3d pu = (c - sign * s * w).normalized(), pv = (c + sign * s * w).normalized();
        set_position(u, pu);
        set_position(v, pv);
        if (!(star_score(u, pu) >= min_height) || !(star_score(v, pv) >= min_height)) continue;
        const double e = star_energy(u, pu, min_height) + star_energy(v, pv, min_height);
        if (e < best) {
          best = e;
          best_u = pu;
          best_v = pv;
        }
      }
    if (!std::isfinite(best)) {
      set_position(u, saved_u);
      set_position(v, saved_v);
      return false;
    }
    set_position(u, best_u);
    set_position(v, best_v);
    for (int round = 0; round < 2; ++round) {
      optimise(v);
      optimise(u);
    }
    return true;
  }

  // Moves w to the centroid of its own kernel when that raises the smallest height of its faces (it opens up the
  // thin angles that make a neighbour's kernel thin). True when w moved.
  bool centre(int w) {
    const Eigen::Vector3d x = position(w);
    const std::optional<Eigen::Vector3d> c = kernel_centroid(w, x);
    if (!c || !(star_score(w, *c) > star_score(w, x))) return false;
    set_position(w, *c);
    return true;
  }

  // The centroid of v's one-ring kernel (one_ring_kernel_centroid) about the sphere point c.
  std::optional<Eigen::Vector3d> kernel_centroid(int v, const Eigen::Vector3d& c) const {
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> link;
    for (int f : mesh_.faces_of(v)) {
      int k = 0;
      while (mesh_.faces()(f, k) != v) ++k;
      link.emplace_back(position(mesh_.faces()(f, (k + 1) % 3)), position(mesh_.faces()(f, (k + 2) % 3)));
    }
    return one_ring_kernel_centroid(c, link);
  }

  Eigen::Vector3d neighbour_average(int v) const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int f : mesh_.faces_of(v))
      for (int k = 0; k < 3; ++k)
        if (mesh_.faces()(f, k) != v) s += position(mesh_.faces()(f, k));
    return s.normalized();
  }
  void relax(int v) {
    const double floor = std::min(min_height_, std::max(0.0, star_score(v, position(v))));
    const Eigen::Vector3d x = position(v), target = neighbour_average(v);
    if (!target.allFinite()) return;
    for (double t = 1.0; t >= 0.125; t *= 0.5) {
      const Eigen::Vector3d y = ((1 - t) * x + t * target).normalized();
      if (star_score(v, y) >= floor) {
        set_position(v, y);
        return;
      }
    }
  }
  void balance(const std::vector<int>& active) {
    Eigen::MatrixX3d s(static_cast<Eigen::Index>(active.size()), 3);
    for (size_t i = 0; i < active.size(); ++i) s.row(static_cast<Eigen::Index>(i)) = position(active[i]).transpose();
    mobius_balance(s, Eigen::VectorXd::Ones(s.rows()));
    const std::vector<Eigen::Vector3d> saved = u_;
    for (size_t i = 0; i < active.size(); ++i) set_position(active[i], s.row(static_cast<Eigen::Index>(i)).transpose());
    for (int v : active)
      if (!valid(v, position(v))) {
        u_ = saved;
        return;
      }
  }

  // The stretch energy of every live face (each counted once, from its first corner).
  double total_energy(const std::vector<int>& active) const {
    double e = 0;
    for (int v : active)
      for (int f : mesh_.faces_of(v))
        if (mesh_.faces()(f, 0) == v) e += face_energy(f);
    return e;
  }

 private:
  void corners(int f, int v, const Eigen::Vector3d& y, Eigen::Vector3d (&p)[3]) const {
    for (int k = 0; k < 3; ++k) p[k] = mesh_.faces()(f, k) == v ? y : position(mesh_.faces()(f, k));
  }
  double face_energy(int f) const {
    const int v = mesh_.faces()(f, 0);
    Eigen::Vector3d p[3];
    corners(f, v, position(v), p);
    const double twice_area = (p[1] - p[0]).cross(p[2] - p[0]).norm();
    if (!(twice_area > 0)) return std::numeric_limits<double>::infinity();
    return stretch_of(f, p, twice_area);
  }

  // The stretch energy of face f with its sphere corners p (twice_area = |(p1 − p0) × (p2 − p0)| > 0): the
  // surface face's area times Σ_k d_k |X_i − X_j|² / (2 · twice_area²), corner k opposite the edge (i, j).
  double stretch_of(int f, const Eigen::Vector3d (&p)[3], double twice_area) const {
    const FaceTerms& t = terms_[static_cast<size_t>(f)];
    const double s = (p[1] - p[0]).dot(p[2] - p[0]) * t.edge2[0] + (p[2] - p[1]).dot(p[0] - p[1]) * t.edge2[1] +
                     (p[0] - p[2]).dot(p[1] - p[2]) * t.edge2[2];
    return t.area * s / (2 * twice_area * twice_area);
  }

  // The surface side of face f's stretch (its area, floored, and the squared length of the edge opposite each
  // corner), computed once per face and corner set instead of at every energy evaluation.
  struct FaceTerms {
    double area = 0;
    double edge2[3] = {0, 0, 0};
  };
  void refresh_terms(int f) {
    const int a = mesh_.faces()(f, 0), b = mesh_.faces()(f, 1), c = mesh_.faces()(f, 2);
    const Eigen::Vector3d xa = x_.row(a).transpose(), xb = x_.row(b).transpose(), xc = x_.row(c).transpose();
    FaceTerms& t = terms_[static_cast<size_t>(f)];
    t.area = std::max(0.5 * (xb - xa).cross(xc - xa).norm(), area_floor_);
    t.edge2[0] = (xb - xc).squaredNorm();
    t.edge2[1] = (xc - xa).squaredNorm();
    t.edge2[2] = (xa - xb).squaredNorm();
  }

  const ProgressiveMesh& mesh_;
  const Eigen::MatrixX3d& x_;  // the surface (the input normalised to area 4π)
  std::vector<Eigen::Vector3d> u_;  // the sphere positions (contiguous: the hot loops read a star's corners)
  std::vector<FaceTerms> terms_;    // per face, for its present corners (star_changed)
  double min_height_;
  double area_floor_ = 0;
};

// How the vertices are spread between the splits (see progressive_embedding.hpp, step 4).
enum class Relaxation { Uniform, Stretch };
// How a split places its vertices (progressive_embedding.hpp, step 3): v in its own kernel first (the pair only
// when that fails the margin), or u and v together in u's old kernel first.
enum class Placement { VertexFirst, PairFirst };

// The smallest area ratio (a_f / Σa) / (A_f / ΣA) over the faces with surface area (sphere chord triangles against
// the surface): how far the most compressed face fell below its area share; 0 for a failed embedding.
double smallest_area_ratio(const Eigen::MatrixX3i& faces, const Eigen::MatrixX3d& surface, const Eigen::MatrixX3d& sphere) {
  if (sphere.rows() != surface.rows()) return 0;
  Eigen::VectorXd a(faces.rows()), s(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const auto twice_area = [&](const Eigen::MatrixX3d& x) {
      return (x.row(faces(f, 1)) - x.row(faces(f, 0))).cross(x.row(faces(f, 2)) - x.row(faces(f, 0))).norm();
    };
    a[f] = twice_area(sphere);
    s[f] = twice_area(surface);
  }
  const double a_total = a.sum(), s_total = s.sum();  // once: summed inside the loop they made this O(F²)
  double smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    if (s[f] > 0) smallest = std::min(smallest, (a[f] / a_total) / (s[f] / s_total));
  return std::isfinite(smallest) ? smallest : 0;
}

// Spreads the vertices within `rings` rings of u (a neighbourhood too crowded for a placement): five sweeps, each
// vertex to the centroid of its own kernel when that opens its thinnest face, then a stretch descent move.
void spread_neighbourhood(SphereEmbedding& sphere, const ProgressiveMesh& mesh, int u, int rings) {
  std::vector<int> ring = {u};
  for (int r = 0; r < rings; ++r)
    for (int w : std::vector<int>(ring))
      for (int x : mesh.neighbours(w)) ring.push_back(x);
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  for (int sweep = 0; sweep < 5; ++sweep)
    for (int w : ring) {
      sphere.centre(w);
      sphere.optimise(w);
    }
}

struct Embedding {
  Eigen::MatrixX3d positions;
  double stretch = std::numeric_limits<double>::infinity();  // total stretch energy of the result
  std::string failure;                                         // empty when every split found a kernel point
  int levels = 0;
  long moves = 0, spread_neighbourhoods = 0;
  bool gave_up = false;  // the uniform spreading stopped at ProgressiveOptions::uniform_max_spreads
};

// The base tetrahedron and the splits of `collapses` (in reverse) on `mesh` (at its 4-vertex state, left at the
// full mesh), spreading the vertices with `relaxation`.
Embedding embed(ProgressiveMesh mesh, const std::vector<ProgressiveMesh::Collapse>& collapses,
                const Eigen::MatrixX3d& surface, const ProgressiveOptions& options, Relaxation relaxation,
                Placement placement, const FlowControl& control) {
  Embedding out;
  const Eigen::Index nv = surface.rows();
  // The tetrahedron: the regular one inscribed in the unit sphere, mirrored if needed to match the orientation.
  SphereEmbedding sphere(mesh, surface, options.min_height);
  std::vector<int> active;
  for (int v = 0; v < static_cast<int>(nv); ++v)
    if (mesh.vertex_alive(v)) active.push_back(v);
  const double s = 1.0 / std::sqrt(3.0);
  const Eigen::Vector3d corners[4] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
  for (size_t i = 0; i < active.size(); ++i) sphere.set_position(active[i], corners[i]);
  if (!sphere.valid(active[0], corners[0])) {
    sphere.set_position(active[0], corners[1]);
    sphere.set_position(active[1], corners[0]);
  }
  for (int v : active)
    if (!sphere.valid(v, sphere.position(v))) {
      out.failure = "the base tetrahedron does not embed";
      return out;
    }

  // Gauss–Seidel sweeps over the live vertices. Stretch: descent moves, ending early once a sweep lowers the
  // energy by less than options.sweep_tolerance of it. Uniform: moves toward the neighbour average, then the
  // uniform Möbius balancing (it stops the slow drift of iterative spherical averaging toward a point).
  const auto relax_all = [&](int sweeps) {
    for (int sweep = 0; sweep < sweeps; ++sweep) {
      out.moves += static_cast<long>(active.size());
      if (relaxation == Relaxation::Uniform) {
        for (int v : active) sphere.relax(v);
        continue;
      }
      double decrease = 0;
      for (int v : active) decrease += sphere.optimise(v);
      if (decrease < options.sweep_tolerance * sphere.total_energy(active)) break;
    }
    if (relaxation == Relaxation::Uniform) sphere.balance(active);
  };
  double next_level = options.level_growth * static_cast<double>(active.size());
  for (auto it = collapses.rbegin(); it != collapses.rend(); ++it) {
    const int v = it->removed, u = it->kept;
    // Centroid of u's kernel before the split (place_pair); v in its own kernel (place) when that fails.
    const std::optional<Eigen::Vector3d> old_kernel = sphere.kernel_centroid(u, sphere.position(u));
    mesh.split(*it);
    sphere.star_changed(v);
    std::vector<int> apexes;
    for (int f : it->killed)
      for (int k = 0; k < 3; ++k)
        if (mesh.faces()(f, k) != u && mesh.faces()(f, k) != v) apexes.push_back(mesh.faces()(f, k));
    const bool pair = placement == Placement::PairFirst && old_kernel &&
                      sphere.place_pair(v, u, *old_kernel, apexes, options.min_height);
    bool placed = pair || sphere.place(v, u, options.min_height);
    // A kernel too thin for the height margin in double precision (a crowded neighbourhood of u): v is collapsed
    // back, u's neighbourhood (2, 3, 4, 5, 5 rings) is spread — each vertex to the centroid of its own kernel when
    // that opens its thinnest face, then a stretch descent move — and the split is tried again. The last two tries
    // accept 1/10 and 3/100 of the height margin (still 10× and 3× the verification's degenerate_height); the moves
    // that follow never lower a star's smallest height below the margin or its present value.
    constexpr double kRetryHeight[] = {1, 1, 1, 0.1, 0.03};  // of min_height; 0.03e-12 is 3× degenerate_height
    for (int retry = 0; retry < 5 && !placed; ++retry) {
      if (relaxation == Relaxation::Uniform && options.uniform_max_spreads > 0 &&
          out.spread_neighbourhoods >= options.uniform_max_spreads) {
        out.failure = "given up: a placement needed more than " + std::to_string(options.uniform_max_spreads) +
                      " neighbourhood spreads (a crowded thin part) at " + std::to_string(active.size()) + " vertices";
        out.gave_up = true;
        return out;
      }
      const profile::ScopedStage stage("map.progressive spread for a placement");
      const ProgressiveMesh::Collapse again = mesh.collapse(v, u);
      sphere.star_changed(u);
      spread_neighbourhood(sphere, mesh, u, std::min(retry, 3) + 2);
      ++out.spread_neighbourhoods;
      mesh.split(again);
      sphere.star_changed(v);
      placed = sphere.place(v, u, kRetryHeight[retry] * options.min_height);
    }
    if (!placed) {
      out.failure = "no kernel point for vertex " + std::to_string(v) + " in double precision at " +
                    std::to_string(active.size()) + " vertices";
      return out;
    }
    active.push_back(v);
    if (static_cast<double>(active.size()) >= next_level) {
      control.deadline.check("progressive embedding level");
      const profile::ScopedStage stage("map.progressive level sweeps");
      relax_all(options.sweeps_per_level);
      next_level = options.level_growth * static_cast<double>(active.size());
      ++out.levels;
    }
  }
  {
    const profile::ScopedStage stage("map.progressive final sweeps");
    relax_all(options.final_sweeps);
  }
  out.stretch = sphere.total_energy(active);
  out.positions = sphere.positions();
  return out;
}

// "NAME STRETCH (N spread)" for the attempt's message: each embedding's result and how often its placements needed
// a neighbourhood spread ("NAME given up (N spread)" at ProgressiveOptions::uniform_max_spreads).
std::string summary(const char* name, const Embedding& e) {
  const std::string spreads = " (" + std::to_string(e.spread_neighbourhoods) + " spread)";
  return std::string(name) + (e.gave_up ? " given up" : " " + std::to_string(e.stretch)) + spreads;
}

// The embeddings progressive_map runs and the one it keeps.
struct EmbeddingRun {
  enum class Kept { Uniform, Stretch, Paired, UniformInFull };
  Embedding uniform, stretch, paired, uniform_in_full;
  Kept kept = Kept::Stretch;
  const Embedding& chosen() const {
    switch (kept) {
      case Kept::Uniform: return uniform;
      case Kept::Paired: return paired;
      case Kept::UniformInFull: return uniform_in_full;
      case Kept::Stretch: break;
    }
    return stretch;
  }
};

// Both spreadings, the one of lower stretch kept (measured: uniform wins on evenly tessellated tubes — coil,
// dumbbells: area distortion ~2 against ~16 — where the stretch descent's local moves converge slowly; stretch
// wins on decimated meshes with very uneven faces — spines: ~4 against 1e5–1e7 — where equal sphere area per
// vertex is far from equal area per surface area). Then, when needed, the pair placement and the uniform spreading
// without its spread limit (below).
EmbeddingRun run_embeddings(const ProgressiveMesh& mesh, const std::vector<ProgressiveMesh::Collapse>& collapses,
                            const MapContext& context, const ProgressiveOptions& options, const FlowControl& control) {
  using Kept = EmbeddingRun::Kept;
  const Eigen::MatrixX3d& surface = context.normalised_input();
  const auto run_one = [&](const char* stage_name, const ProgressiveOptions& o, Relaxation r, Placement p) {
    const profile::ScopedStage stage(stage_name);
    return embed(mesh, collapses, surface, o, r, p, control);
  };
  EmbeddingRun run;
  run.uniform = run_one("map.progressive embed (uniform)", options, Relaxation::Uniform, Placement::VertexFirst);
  run.stretch = run_one("map.progressive embed (stretch)", options, Relaxation::Stretch, Placement::VertexFirst);
  const bool use_uniform = !run.stretch.failure.empty() ||
                           (run.uniform.failure.empty() && run.uniform.stretch <= run.stretch.stretch);
  run.kept = use_uniform ? Kept::Uniform : Kept::Stretch;
  // A long thin part (a coil's middle) can still end compressed far below its area share, or both embeddings
  // fail: placing each split's pair in u's old kernel (place_pair) is tried then, with stretch spreading, and kept
  // when its most compressed face is less compressed (measured on the generated coils: the fine 12-turn coil with
  // wire 1/20 maps only this way; the fine 6-turn one goes from an area ratio of 1e-23 to 1e-11). It runs only
  // then, so every embedding that kept its faces above the floor is unchanged.
  const double ratio =
      run.chosen().failure.empty() ? smallest_area_ratio(context.faces(), surface, run.chosen().positions) : 0;
  if (ratio < options.pair_placement_below_area_ratio) {
    run.paired = run_one("map.progressive embed (pair placement)", options, Relaxation::Stretch, Placement::PairFirst);
    if (run.paired.failure.empty() && smallest_area_ratio(context.faces(), surface, run.paired.positions) > ratio)
      run.kept = Kept::Paired;
  }
  // The uniform spreading given up (uniform_max_spreads) and nothing else embedded: it runs again without the
  // limit, so the last resort maps every mesh it mapped before.
  if (!run.chosen().failure.empty() && run.uniform.gave_up) {
    ProgressiveOptions unlimited = options;
    unlimited.uniform_max_spreads = 0;
    run.uniform_in_full = run_one("map.progressive embed (uniform, no spread limit)", unlimited, Relaxation::Uniform,
                                  Placement::VertexFirst);
    if (run.uniform_in_full.failure.empty()) run.kept = Kept::UniformInFull;
  }
  return run;
}

// The attempt's message: which embedding was kept, every embedding's stretch and spreads, the kept one's work.
std::string describe(const EmbeddingRun& run, size_t splits) {
  using Kept = EmbeddingRun::Kept;
  const Embedding& chosen = run.chosen();
  const char* kept = run.kept == Kept::Paired          ? "pair placement, stretch"
                     : run.kept == Kept::Stretch       ? "stretch"
                     : run.kept == Kept::UniformInFull ? "uniform (no spread limit)"
                                                       : "uniform";
  std::string tried = summary("uniform", run.uniform) + ", " + summary("stretch", run.stretch);
  if (run.paired.moves > 0) tried += ", " + summary("pair placement", run.paired);
  if (run.uniform_in_full.moves > 0) tried += ", " + summary("uniform without spread limit", run.uniform_in_full);
  return "progressive embedding: " + std::to_string(splits) + " vertex splits, " + kept + " spreading (stretch " +
         std::to_string(chosen.stretch) + "; " + tried + "), " + std::to_string(chosen.levels) + " levels, " +
         std::to_string(chosen.moves) + " vertex moves, " + std::to_string(chosen.spread_neighbourhoods) +
         " neighbourhoods spread for a placement";
}

}  // namespace

std::optional<Eigen::Vector3d> one_ring_kernel_centroid(
    const Eigen::Vector3d& c, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& link) {
  const Eigen::Vector3d helper = std::abs(c.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = helper.cross(c).normalized(), e2 = c.cross(e1);
  double reach = 0;
  for (const auto& [a, b] : link) reach = std::max({reach, (a - c).norm(), (b - c).norm()});
  const double half = std::min(1.0, reach);  // the kernel lies within the ring: a square of this half-width holds it
  std::vector<Eigen::Vector2d> polygon = {{-half, -half}, {half, -half}, {half, half}, {-half, half}}, clipped;
  for (const auto& [a, b] : link) {
    // det(y, a, b) = y·(a × b) > 0 with y = p + s e1 + t e2 (y·c > 0 within the square): a half-plane in (s, t).
    // a × b from differences to c, (a − c) × (b − c) + c × (b − a) (the same vector): accurate when the ring is
    // tiny (a crowded neighbourhood: neighbours 1e-8 apart, where a × b of two nearly parallel unit vectors loses
    // most digits and the clipped polygon missed the kernel).
    const Eigen::Vector3d n = (a - c).cross(b - c) + c.cross(b - a);
    const double c0 = c.dot(n), c1 = e1.dot(n), c2 = e2.dot(n);
    const auto side = [&](const Eigen::Vector2d& q) { return c0 + c1 * q.x() + c2 * q.y(); };
    clipped.clear();
    for (size_t i = 0; i < polygon.size(); ++i) {  // Sutherland & Hodgman 1974, one clipping edge
      const Eigen::Vector2d &p = polygon[i], &q = polygon[(i + 1) % polygon.size()];
      const double sp = side(p), sq = side(q);
      if (sp > 0) clipped.push_back(p);
      if ((sp > 0) != (sq > 0) && sp != sq) clipped.push_back(p + (sp / (sp - sq)) * (q - p));
    }
    polygon.swap(clipped);
    if (polygon.size() < 3) return std::nullopt;
  }
  // Area centroid of the convex polygon (fan from its first corner).
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double area = 0;
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Eigen::Vector2d a = polygon[i] - polygon[0], b = polygon[i + 1] - polygon[0];
    const double w = 0.5 * (a.x() * b.y() - a.y() * b.x());
    centroid += w * (polygon[0] + polygon[i] + polygon[i + 1]) / 3;
    area += w;
  }
  if (!(area > 0)) return std::nullopt;
  centroid /= area;
  return (c + centroid.x() * e1 + centroid.y() * e2).normalized();
}

FlowResult progressive_map(const MapContext& context, const ProgressiveOptions& options, const FlowControl& control) {
  const Clock::time_point t_start = Clock::now();
  FlowResult result;
  result.on_sphere = true;
  FlowStepRecord rec;
  rec.step = 1;
  const Eigen::Index nv = context.vertex_count();
  const auto fail = [&](const std::string& message) {
    result.status = MapStatus::SolverFailed;
    result.failed_check = MapCheck::Solver;
    result.stop = FlowStop::SolverFailed;
    result.message = message;
    rec.accepted = false;
    rec.note = message;
    rec.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
    result.steps.push_back(rec);
    result.vertices = Eigen::MatrixX3d::Constant(nv, 3, std::numeric_limits<double>::quiet_NaN());
    return result;
  };

  ProgressiveMesh mesh(context.faces(), nv);
  std::vector<ProgressiveMesh::Collapse> collapses;
  bool simplified = false;
  {
    const profile::ScopedStage stage("map.progressive simplify");
    simplified = simplify_to_tetrahedron(mesh, context.mesh().vertices, collapses);
  }
  if (!simplified)
    return fail("progressive embedding: no edge passes the link condition at " +
                std::to_string(nv - static_cast<Eigen::Index>(collapses.size())) + " vertices");
  rec.geometry_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();

  const EmbeddingRun run = run_embeddings(mesh, collapses, context, options, control);
  if (!run.chosen().failure.empty())
    return fail("progressive embedding: " + run.stretch.failure + " (uniform spreading: " + run.uniform.failure +
                "; pair placement: " + run.paired.failure + ")");
  result.vertices = run.chosen().positions;
  rec.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  result.steps.push_back(rec);
  result.message = describe(run, collapses.size());
  result.keep_normalisation = true;
  return result;
}

}  // namespace wish::spherical
