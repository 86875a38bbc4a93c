#include "core/spherical_map/progressive_embedding.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <queue>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "core/spherical_map/mobius.hpp"

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
  using Entry = std::tuple<double, int, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const auto push_edges_of_faces = [&] {
    for (Eigen::Index f = 0; f < mesh.faces().rows(); ++f) {
      if (!mesh.face_alive(static_cast<int>(f))) continue;
      for (int k = 0; k < 3; ++k) {
        const int a = mesh.faces()(f, k), b = mesh.faces()(f, (k + 1) % 3);
        if (a < b) queue.emplace((x.row(a) - x.row(b)).norm(), a, b);
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
    for (int w : mesh.neighbours(kept)) queue.emplace((x.row(kept) - x.row(w)).norm(), std::min(kept, w), std::max(kept, w));
  }
  return true;
}

// The sphere positions and the tests every move must pass.
class SphereEmbedding {
 public:
  SphereEmbedding(const ProgressiveMesh& mesh, Eigen::Index vertex_count, double min_height)
      : mesh_(mesh), u_(Eigen::MatrixX3d::Zero(vertex_count, 3)), min_height_(min_height) {}

  Eigen::MatrixX3d& positions() { return u_; }

  // Smallest chord-triangle height of v's faces with v at y; −1 when one of them is not positively oriented.
  double star_score(int v, const Eigen::Vector3d& y) const {
    double worst = std::numeric_limits<double>::infinity();
    for (int f : mesh_.faces_of(v)) {
      Eigen::Vector3d p[3];
      for (int k = 0; k < 3; ++k) p[k] = mesh_.faces()(f, k) == v ? y : Eigen::Vector3d(u_.row(mesh_.faces()(f, k)));
      const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
      if (!(n.dot(p[0] + p[1] + p[2]) > 0)) return -1;
      const double longest = std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
      worst = std::min(worst, n.norm() / longest);
    }
    return worst;
  }
  bool valid(int v, const Eigen::Vector3d& y) const { return star_score(v, y) >= min_height_; }

  // The uniform (Tutte) target: the normalised sum of v's neighbours, each counted once per face.
  Eigen::Vector3d neighbour_average(int v) const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int f : mesh_.faces_of(v))
      for (int k = 0; k < 3; ++k)
        if (mesh_.faces()(f, k) != v) s += u_.row(mesh_.faces()(f, k)).transpose();
    return s.normalized();
  }

  // Moves v toward its neighbour average, as far as its star stays valid (tries t = 1, ½, ¼, ⅛).
  void relax(int v) {
    const Eigen::Vector3d x = u_.row(v).transpose(), target = neighbour_average(v);
    if (!target.allFinite()) return;
    for (double t = 1.0; t >= 0.125; t *= 0.5) {
      const Eigen::Vector3d y = ((1 - t) * x + t * target).normalized();
      if (valid(v, y)) {
        u_.row(v) = y.transpose();
        return;
      }
    }
  }

  // Re-inserts v (just split off u) inside the kernel of its one-ring: at its neighbour average if that is in the
  // kernel, else near u inside the cone where the kernel reaches u — then moved toward the average as far as it
  // stays valid. The cone (Praun & Hoppe's argument): in u's tangent plane, let w1 and w2 be the third vertices of
  // the faces (u, v, w1) and (v, u, w2), and α ∈ (0, 2π) the angle of the sector from w2 counter-clockwise to w1
  // (the sector v's faces took from u's star). Points u + δd see the edges uw1 and w2u from the correct side iff d
  // lies within (θ2 + max(0, α − π), θ2 + min(π, α)), which holds the bisector θ2 + α/2; every other link edge
  // (a, b) of v bounded the valid face (u, a, b), so small enough δ keeps it valid too.
  bool place(int v, int u) {
    const Eigen::Vector3d target = neighbour_average(v);
    if (target.allFinite() && valid(v, target)) {
      u_.row(v) = target.transpose();
      return true;
    }
    const Eigen::Vector3d p = u_.row(u).transpose();
    const Eigen::Vector3d helper = std::abs(p.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = helper.cross(p).normalized(), e2 = p.cross(e1);
    const auto angle_of = [&](int w) {
      const Eigen::Vector3d t = u_.row(w).transpose() - p;
      return std::atan2(t.dot(e2), t.dot(e1));
    };
    int w1 = -1, w2 = -1;
    double reach = std::numeric_limits<double>::infinity();
    for (int f : mesh_.faces_of(v))
      for (int k = 0; k < 3; ++k) {
        const int a = mesh_.faces()(f, k), b = mesh_.faces()(f, (k + 1) % 3), c = mesh_.faces()(f, (k + 2) % 3);
        if (a == u && b == v) w1 = c;
        if (a == v && b == u) w2 = c;
        if (a != u && a != v) reach = std::min(reach, (u_.row(a).transpose() - p).norm());
      }
    if (w1 < 0 || w2 < 0 || !std::isfinite(reach)) return false;
    const double theta2 = angle_of(w2);
    double alpha = angle_of(w1) - theta2;
    while (alpha <= 0) alpha += 2 * std::numbers::pi;
    while (alpha >= 2 * std::numbers::pi) alpha -= 2 * std::numbers::pi;
    const double width = std::min(alpha, 2 * std::numbers::pi - alpha);
    double best = -1;
    Eigen::Vector3d best_y = p;
    for (double delta = 0.5 * reach; delta > 1e-13 && best < min_height_; delta *= 0.5)
      for (int j = -4; j <= 4; ++j) {
        const double angle = theta2 + 0.5 * alpha + j * width / 10;
        const Eigen::Vector3d y = (p + delta * (std::cos(angle) * e1 + std::sin(angle) * e2)).normalized();
        const double score = star_score(v, y);
        if (score > best) {
          best = score;
          best_y = y;
        }
      }
    if (best < min_height_) return false;
    u_.row(v) = best_y.transpose();
    if (target.allFinite())
      for (double t = 0.5; t >= 1.0 / 64; t *= 0.5) {
        const Eigen::Vector3d y = ((1 - t) * best_y + t * target).normalized();
        if (valid(v, y)) {
          u_.row(v) = y.transpose();
          break;
        }
      }
    return true;
  }

  // Möbius balancing of the active vertices with uniform weights, kept only if every live face stays valid.
  void balance(const std::vector<int>& active) {
    Eigen::MatrixX3d s(static_cast<Eigen::Index>(active.size()), 3);
    for (size_t i = 0; i < active.size(); ++i) s.row(static_cast<Eigen::Index>(i)) = u_.row(active[i]);
    mobius_balance(s, Eigen::VectorXd::Ones(s.rows()));
    const Eigen::MatrixX3d saved = u_;
    for (size_t i = 0; i < active.size(); ++i) u_.row(active[i]) = s.row(static_cast<Eigen::Index>(i));
    for (int v : active)
      if (!valid(v, u_.row(v).transpose())) {
        u_ = saved;
        return;
      }
  }

 private:
  const ProgressiveMesh& mesh_;
  Eigen::MatrixX3d u_;
  double min_height_;
};

}  // namespace

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
  if (!simplify_to_tetrahedron(mesh, context.mesh().vertices, collapses))
    return fail("progressive embedding: no edge passes the link condition at " +
                std::to_string(nv - static_cast<Eigen::Index>(collapses.size())) + " vertices");
  rec.geometry_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();

  // The tetrahedron: the regular one inscribed in the unit sphere, mirrored if needed to match the orientation.
  SphereEmbedding sphere(mesh, nv, options.min_height);
  std::vector<int> active;
  for (int v = 0; v < static_cast<int>(nv); ++v)
    if (mesh.vertex_alive(v)) active.push_back(v);
  const double s = 1.0 / std::sqrt(3.0);
  const Eigen::Vector3d corners[4] = {{s, s, s}, {s, -s, -s}, {-s, s, -s}, {-s, -s, s}};
  for (size_t i = 0; i < active.size(); ++i) sphere.positions().row(active[i]) = corners[i].transpose();
  if (!sphere.valid(active[0], corners[0])) {
    sphere.positions().row(active[0]) = corners[1].transpose();
    sphere.positions().row(active[1]) = corners[0].transpose();
  }
  for (int v : active)
    if (!sphere.valid(v, sphere.positions().row(v).transpose()))
      return fail("progressive embedding: the base tetrahedron does not embed");

  const auto relax_all = [&](int sweeps) {
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (int v : active) sphere.relax(v);
    sphere.balance(active);
  };
  double next_level = options.level_growth * static_cast<double>(active.size());
  int levels = 0;
  long relaxed_neighbourhoods = 0;
  for (auto it = collapses.rbegin(); it != collapses.rend(); ++it) {
    mesh.split(*it);
    // Should no candidate of the kernel keep min_height in double precision (a crowded neighbourhood of u), the
    // neighbourhood is relaxed (u's neighbours and theirs, v still out) and the placement tried again.
    for (int retry = 0; retry < 3 && !sphere.place(it->removed, it->kept); ++retry) {
      std::vector<int> ring = mesh.neighbours(it->kept);
      for (int w : std::vector<int>(ring))
        for (int x : mesh.neighbours(w)) ring.push_back(x);
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      ring.erase(std::remove(ring.begin(), ring.end(), it->removed), ring.end());
      for (int sweep = 0; sweep < 10; ++sweep)
        for (int w : ring) sphere.relax(w);
      ++relaxed_neighbourhoods;
    }
    if (!sphere.valid(it->removed, sphere.positions().row(it->removed).transpose()))
      return fail("progressive embedding: no kernel point for vertex " + std::to_string(it->removed) +
                  " in double precision at " + std::to_string(active.size()) + " vertices");
    active.push_back(it->removed);
    if (static_cast<double>(active.size()) >= next_level) {
      control.deadline.check("progressive embedding level");
      relax_all(options.sweeps_per_level);
      next_level = options.level_growth * static_cast<double>(active.size());
      ++levels;
    }
  }
  relax_all(options.final_sweeps);
  result.vertices = sphere.positions();
  rec.seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  result.steps.push_back(rec);
  result.message = "progressive embedding: " + std::to_string(collapses.size()) + " vertex splits, " +
                   std::to_string(levels) + " relaxation levels, " + std::to_string(relaxed_neighbourhoods) +
                   " neighbourhoods relaxed for a placement";
  result.keep_normalisation = true;
  return result;
}

}  // namespace wish::spherical
