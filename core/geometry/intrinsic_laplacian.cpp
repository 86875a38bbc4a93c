// Intrinsic mollification + intrinsic Delaunay edge flips on a halfedge Δ-complex (see the header for the methods).
// Halfedge h = 3f + k of face f runs from corner k to corner k+1; its length is stored per halfedge (equal on
// both halves of an edge).
#include "core/geometry/intrinsic_laplacian.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "core/common/enum_names.hpp"
#include "core/common/errors.hpp"
#include "core/geometry/laplacian_kind_names.hpp"

namespace wish::geometry {

const char* to_string(LaplacianKind kind) { return kLaplacianKindNames.name(kind); }

LaplacianKind laplacian_kind_from_name(const char* name) {
  return kLaplacianKindNames.parse(name, "Laplacian", "laplacian");
}

double triangle_area_from_lengths(double a, double b, double c) {
  // Kahan: sort a ≥ b ≥ c, A = ¼ √((a+(b+c))(c−(a−b))(c+(a−b))(a+(b−c))).
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double p = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return p > 0 ? 0.25 * std::sqrt(p) : 0.0;
}

Eigen::VectorXd mollified_face_areas(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     double mollify_delta) {
  const Eigen::Index nf = faces.rows();
  Eigen::MatrixX3d l(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) l(f, k) = (vertices.row(faces(f, (k + 1) % 3)) - vertices.row(faces(f, k))).norm();
  const double margin = nf > 0 ? mollify_delta * l.mean() : 0.0;
  double eps = 0;
  for (Eigen::Index f = 0; f < nf; ++f)
    eps = std::max(eps, margin - std::min({l(f, 0) + l(f, 1) - l(f, 2), l(f, 1) + l(f, 2) - l(f, 0),
                                           l(f, 2) + l(f, 0) - l(f, 1)}));
  Eigen::VectorXd areas(nf);
  for (Eigen::Index f = 0; f < nf; ++f) areas[f] = triangle_area_from_lengths(l(f, 0) + eps, l(f, 1) + eps, l(f, 2) + eps);
  return areas;
}

namespace {

// Cotangent of the angle opposite side c in the triangle with sides a, b, c: (a² + b² − c²) / (4A).
double cot_opposite(double a, double b, double c) {
  const double area = triangle_area_from_lengths(a, b, c);
  return (a * a + b * b - c * c) / (4.0 * area);
}

struct HalfedgeMesh {
  std::vector<std::array<int, 3>> face;  // corner vertices
  std::vector<int> twin;                 // per halfedge
  std::vector<double> length;            // per halfedge

  static int next(int h) { return 3 * (h / 3) + (h % 3 + 1) % 3; }
  int tail(int h) const { return face[static_cast<size_t>(h / 3)][static_cast<size_t>(h % 3)]; }
  double len(int h) const { return length[static_cast<size_t>(h)]; }
  // Per face, the area from its three lengths (Kahan's formula is symmetric in them, so this is the value
  // cot_opposite() computes from any corner); empty while the lengths change (flips). Computed once instead of
  // once per cotangent: five area evaluations per face fewer in every operator.
  std::vector<double> face_area;
  void cache_face_areas() {
    face_area.resize(face.size());
    for (size_t f = 0; f < face.size(); ++f)
      face_area[f] = triangle_area_from_lengths(length[3 * f], length[3 * f + 1], length[3 * f + 2]);
  }
  // cot of the corner opposite halfedge h in its face.
  double cot_opposite_of(int h) const {
    const int h1 = next(h), h2 = next(h1);
    if (face_area.empty()) return cot_opposite(len(h1), len(h2), len(h));
    const double a = len(h1), b = len(h2), c = len(h);
    return (a * a + b * b - c * c) / (4.0 * face_area[static_cast<size_t>(h / 3)]);
  }
  double edge_cot_sum(int h) const { return cot_opposite_of(h) + cot_opposite_of(twin[static_cast<size_t>(h)]); }
};

// The working copy of an operator: the connectivity (flips rewrite it) and lengths of zero.
HalfedgeMesh working_mesh(const HalfedgeConnectivity& connectivity) {
  HalfedgeMesh m;
  m.face = connectivity.corners;
  m.twin = connectivity.twin;
  m.length.assign(m.twin.size(), 0.0);
  return m;
}

// Flips the edge of halfedge h (faces f0 = (a, b, c) with h = a→b, f1 = (b, a, d) with twin b→a) into the
// diagonal c–d: new faces (d, b, c) and (c, a, d). The new length is |c − d| with both triangles laid out flat
// on either side of ab. Returns false (and changes nothing) when the layout is not a proper flip.
bool flip(HalfedgeMesh& m, int h, std::vector<int>& degree) {
  const int t = m.twin[static_cast<size_t>(h)];
  const int f0 = h / 3, f1 = t / 3;
  if (f0 == f1) return false;
  const int h1 = HalfedgeMesh::next(h), h2 = HalfedgeMesh::next(h1);
  const int t1 = HalfedgeMesh::next(t), t2 = HalfedgeMesh::next(t1);
  const int a = m.tail(h), b = m.tail(h1), c = m.tail(h2), d = m.tail(t2);
  if (degree[static_cast<size_t>(a)] < 3 || degree[static_cast<size_t>(b)] < 3) return false;
  const double lab = m.len(h), lbc = m.len(h1), lca = m.len(h2), lad = m.len(t1), ldb = m.len(t2);
  const double cx = (lab * lab + lca * lca - lbc * lbc) / (2 * lab);
  const double cy = std::sqrt(std::max(0.0, lca * lca - cx * cx));
  const double dx = (lab * lab + lad * lad - ldb * ldb) / (2 * lab);
  const double dy = -std::sqrt(std::max(0.0, lad * lad - dx * dx));
  const double lcd = std::hypot(cx - dx, cy - dy);
  // Both new triangles must be proper (the quad is convex at a and b for a non-Delaunay edge; checked anyway).
  if (!(lcd > 0) || !std::isfinite(lcd) || triangle_area_from_lengths(ldb, lbc, lcd) <= 0 ||
      triangle_area_from_lengths(lca, lad, lcd) <= 0)
    return false;
  // Old halfedges keep their outer twins; new slots: f0 = (d→b, b→c, c→d), f1 = (c→a, a→d, d→c).
  const std::array<int, 4> old_outer{t2, h1, h2, t1};
  const std::array<int, 4> new_slot{3 * f0 + 0, 3 * f0 + 1, 3 * f1 + 0, 3 * f1 + 1};
  std::array<int, 4> outer_twin{};
  std::array<double, 4> outer_len{};
  for (int k = 0; k < 4; ++k) {
    outer_twin[static_cast<size_t>(k)] = m.twin[static_cast<size_t>(old_outer[static_cast<size_t>(k)])];
    outer_len[static_cast<size_t>(k)] = m.len(old_outer[static_cast<size_t>(k)]);
  }
  m.face[static_cast<size_t>(f0)] = {d, b, c};
  m.face[static_cast<size_t>(f1)] = {c, a, d};
  for (int k = 0; k < 4; ++k) {
    int tw = outer_twin[static_cast<size_t>(k)];
    for (int j = 0; j < 4; ++j)  // a twin inside the flipped pair moves with it
      if (tw == old_outer[static_cast<size_t>(j)]) {
        tw = new_slot[static_cast<size_t>(j)];
        break;
      }
    const int s = new_slot[static_cast<size_t>(k)];
    m.twin[static_cast<size_t>(s)] = tw;
    m.twin[static_cast<size_t>(tw)] = s;
    m.length[static_cast<size_t>(s)] = outer_len[static_cast<size_t>(k)];
  }
  const int e0 = 3 * f0 + 2, e1 = 3 * f1 + 2;  // c→d and d→c
  m.twin[static_cast<size_t>(e0)] = e1;
  m.twin[static_cast<size_t>(e1)] = e0;
  m.length[static_cast<size_t>(e0)] = m.length[static_cast<size_t>(e1)] = lcd;
  --degree[static_cast<size_t>(a)];
  --degree[static_cast<size_t>(b)];
  ++degree[static_cast<size_t>(c)];
  ++degree[static_cast<size_t>(d)];
  return true;
}

}  // namespace

// Twins from the halfedges grouped by tail vertex (counting sort): the twin of a→b is the halfedge b→a among b's
// outgoing ones, a scan of b's few. (A hash map of all directed edges did the same at 4 % of a nucleus map's CPU, for
// every operator of every flow step.) With several a→b halfedges (a non-manifold input) the last one is the twin,
// as before.
HalfedgeConnectivity halfedge_connectivity(const Eigen::MatrixX3i& faces) {
  HalfedgeConnectivity c;
  const Eigen::Index nf = faces.rows();
  c.corners.resize(static_cast<size_t>(nf));
  c.twin.assign(static_cast<size_t>(3 * nf), -1);
  if (nf == 0) return c;
  if (faces.minCoeff() < 0) throw InvalidInputError("index_out_of_range", "intrinsic Laplacian: negative face index");
  const auto tail = [&](int h) { return c.corners[static_cast<size_t>(h / 3)][static_cast<size_t>(h % 3)]; };
  const size_t nv = static_cast<size_t>(faces.maxCoeff()) + 1;
  std::vector<int> first(nv + 1, 0);  // halfedges with tail v: out[first[v] .. first[v + 1])
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      c.corners[static_cast<size_t>(f)][static_cast<size_t>(k)] = faces(f, k);
      ++first[static_cast<size_t>(faces(f, k)) + 1];
    }
  for (size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
  std::vector<int> out(static_cast<size_t>(3 * nf)), fill(first.begin(), first.end() - 1);
  for (int h = 0; h < static_cast<int>(3 * nf); ++h) out[static_cast<size_t>(fill[static_cast<size_t>(tail(h))]++)] = h;
  for (int h = 0; h < static_cast<int>(3 * nf); ++h) {
    const int a = tail(h), b = tail(HalfedgeMesh::next(h));
    int twin = -1;
    for (int q = first[static_cast<size_t>(b)]; q < first[static_cast<size_t>(b) + 1]; ++q) {
      const int g = out[static_cast<size_t>(q)];
      if (tail(HalfedgeMesh::next(g)) == a) twin = g;  // ascending g: the last match wins
    }
    if (twin < 0)
      throw WishError(ErrorCategory::Unmappable, "not_closed", "intrinsic Laplacian: edge (" + std::to_string(a) + ", " +
                                                  std::to_string(b) +
                                                  ") has no opposite halfedge (the mesh must be closed and oriented)");
    c.twin[static_cast<size_t>(h)] = twin;
  }
  return c;
}

IntrinsicOperator intrinsic_operator(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     const IntrinsicOptions& options) {
  return intrinsic_operator(vertices, faces, halfedge_connectivity(faces), options);
}

IntrinsicOperator intrinsic_operator(const Eigen::MatrixX3d& vertices, const Eigen::MatrixX3i& faces,
                                     const HalfedgeConnectivity& connectivity, const IntrinsicOptions& options) {
  if (connectivity.twin.size() != static_cast<size_t>(3 * faces.rows()) ||
      connectivity.corners.size() != static_cast<size_t>(faces.rows()))
    throw std::invalid_argument("intrinsic_operator: the halfedge connectivity is not that of these faces");
  IntrinsicOperator out;
  IntrinsicStats& stats = out.stats;
  stats.kind = options.kind;
  const Eigen::Index nv = vertices.rows(), nf = faces.rows();
  HalfedgeMesh m = working_mesh(connectivity);
  stats.edges = static_cast<long>(3 * nf / 2);

  // 1. Lengths and mollification.
  double mean = 0;
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const double l = (vertices.row(faces(f, (k + 1) % 3)) - vertices.row(faces(f, k))).norm();
      m.length[static_cast<size_t>(3 * f + k)] = l;
      mean += l;
    }
  mean = nf > 0 ? mean / static_cast<double>(3 * nf) : 1.0;
  const double margin = options.kind == LaplacianKind::Extrinsic ? 0.0 : options.mollify_delta * mean;
  double eps = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const double l0 = m.len(static_cast<int>(3 * f)), l1 = m.len(static_cast<int>(3 * f + 1)),
                 l2 = m.len(static_cast<int>(3 * f + 2));
    const double slack = std::min({l0 + l1 - l2, l1 + l2 - l0, l2 + l0 - l1});
    const Eigen::Vector3d p0 = vertices.row(faces(f, 0)), p1 = vertices.row(faces(f, 1)), p2 = vertices.row(faces(f, 2));
    if (!((p1 - p0).cross(p2 - p0).norm() > 1e-14 * mean * mean)) ++stats.zero_area_faces;
    if (slack < margin) ++stats.mollified_faces;
    eps = std::max(eps, margin - slack);
  }
  if (eps > 0)
    for (double& l : m.length) l += eps;
  stats.epsilon = eps;
  stats.relative_epsilon = eps / mean;
  m.cache_face_areas();

  // Input-face areas and cotangents from the (mollified) lengths.
  out.input_face_areas.resize(nf);
  out.input_cotangents.resize(nf, 3);
  for (Eigen::Index f = 0; f < nf; ++f) {
    out.input_face_areas[f] = m.face_area[static_cast<size_t>(f)];
    // Corner k is opposite halfedge (k+1) (from corner k+1 to k+2).
    for (int k = 0; k < 3; ++k) out.input_cotangents(f, k) = m.cot_opposite_of(static_cast<int>(3 * f + (k + 1) % 3));
  }
  for (size_t h = 0; h < m.twin.size(); ++h)
    if (static_cast<int>(h) < m.twin[h] && m.edge_cot_sum(static_cast<int>(h)) < 0) ++stats.negative_weights_before;

  // 2. Intrinsic Delaunay flips.
  if (options.kind == LaplacianKind::IntrinsicDelaunay) {
    m.face_area.clear();  // flips change lengths: areas from the lengths again until the flips are done
    std::vector<int> degree(static_cast<size_t>(nv), 0);
    for (const auto& fc : m.face)
      for (int v : fc) ++degree[static_cast<size_t>(v)];
    std::deque<int> queue;
    std::vector<char> queued(m.twin.size(), 0);
    auto push = [&](int h) {
      const int e = std::min(h, m.twin[static_cast<size_t>(h)]);
      if (!queued[static_cast<size_t>(e)]) {
        queued[static_cast<size_t>(e)] = 1;
        queue.push_back(e);
      }
    };
    for (size_t h = 0; h < m.twin.size(); ++h) push(static_cast<int>(h));
    const long cap = static_cast<long>(options.max_flips_per_edge) * std::max<long>(1, stats.edges);
    // Small tolerance: cocircular quads (cot sum ≈ 0) must not ping-pong.
    const double tol = 1e-10;
    while (!queue.empty()) {
      const int e = queue.front();
      queue.pop_front();
      queued[static_cast<size_t>(e)] = 0;
      // The edge may have moved slots since it was queued: re-read it at its current halfedge.
      if (!(m.edge_cot_sum(e) < -tol)) continue;
      if (stats.flips >= cap) {
        stats.flip_cap_hit = true;
        break;
      }
      const int t = m.twin[static_cast<size_t>(e)];
      const int f0 = e / 3, f1 = t / 3;
      if (!flip(m, e, degree)) continue;
      ++stats.flips;
      for (int k = 0; k < 2; ++k) {  // the four outer edges of the new pair
        push(3 * f0 + k);
        push(3 * f1 + k);
      }
    }
  }

  // 3. Assemble L and M on the (flipped) triangulation.
  if (m.face_area.empty()) m.cache_face_areas();
  out.faces.resize(nf, 3);
  out.mass = Eigen::VectorXd::Zero(nv);
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto& fc = m.face[static_cast<size_t>(f)];
    for (int k = 0; k < 3; ++k) out.faces(f, k) = fc[static_cast<size_t>(k)];
    const double area = m.face_area[static_cast<size_t>(f)];
    for (int k = 0; k < 3; ++k) out.mass[fc[static_cast<size_t>(k)]] += area / 3.0;
  }
  // w_ij = ½ Σ cot over the halfedges between i and j (two on a mesh edge, more on a Δ-complex edge after flips).
  // The halfedges are grouped by their lower endpoint (counting sort), then ordered by the upper one and their own
  // index, so the edges come out sorted by (i, j) and each weight is summed in halfedge order; L is then written in
  // compressed columns directly. (A hash map of the vertex pairs and a triplet list did the same at ~3 ms per
  // operator on 10K vertices, each flow step.)
  struct Halfedge {
    int upper, h;
    bool operator<(const Halfedge& o) const { return upper != o.upper ? upper < o.upper : h < o.h; }
  };
  std::vector<int> first(static_cast<size_t>(nv) + 1, 0);
  const int halfedges = static_cast<int>(m.twin.size());
  for (int h = 0; h < halfedges; ++h) {
    const int i = m.tail(h), j = m.tail(HalfedgeMesh::next(h));
    if (i != j) ++first[static_cast<size_t>(std::min(i, j)) + 1];  // a loop edge x_i − x_i contributes nothing
  }
  for (Eigen::Index v = 0; v < nv; ++v) first[static_cast<size_t>(v) + 1] += first[static_cast<size_t>(v)];
  std::vector<Halfedge> by_lower(static_cast<size_t>(first.back()));
  {
    std::vector<int> fill(first.begin(), first.end() - 1);
    for (int h = 0; h < halfedges; ++h) {
      const int i = m.tail(h), j = m.tail(HalfedgeMesh::next(h));
      if (i != j) by_lower[static_cast<size_t>(fill[static_cast<size_t>(std::min(i, j))]++)] = {std::max(i, j), h};
    }
  }
  Eigen::VectorXd diag = Eigen::VectorXd::Zero(nv);
  out.edges.reserve(by_lower.size() / 2);
  for (Eigen::Index lo = 0; lo < nv; ++lo) {
    const auto begin = by_lower.begin() + first[static_cast<size_t>(lo)], end = by_lower.begin() + first[static_cast<size_t>(lo) + 1];
    std::sort(begin, end);
    for (auto it = begin; it != end;) {
      const int hi = it->upper;
      double w = 0;
      for (; it != end && it->upper == hi; ++it) w += 0.5 * m.cot_opposite_of(it->h);
      if (options.kind == LaplacianKind::IntrinsicDelaunay && w < 0) {
        ++stats.negative_weights_after;  // only after a flip cap, or rounding on cocircular quads
        w = 0;
      }
      out.edges.push_back({static_cast<int>(lo), hi, w});
      diag[lo] += w;
      diag[hi] += w;
    }
  }
  // Column c: rows i < c (edges (i, c), met in increasing i), the diagonal, rows j > c (edges (c, j), increasing j).
  Eigen::SparseMatrix<double>& l = out.laplacian;
  l.resize(nv, nv);
  l.resizeNonZeros(static_cast<Eigen::Index>(2 * out.edges.size()) + nv);
  int* outer = l.outerIndexPtr();
  int* inner = l.innerIndexPtr();
  double* value = l.valuePtr();
  std::vector<int> next(static_cast<size_t>(nv), 1);  // entries per column (the diagonal), then the write position
  for (const IntrinsicEdgeWeight& e : out.edges) ++next[static_cast<size_t>(e.i)], ++next[static_cast<size_t>(e.j)];
  outer[0] = 0;
  for (Eigen::Index c = 0; c < nv; ++c) {
    outer[c + 1] = outer[c] + next[static_cast<size_t>(c)];
    next[static_cast<size_t>(c)] = outer[c];
  }
  auto put = [&](int column, int row, double v) {
    const int p = next[static_cast<size_t>(column)]++;
    inner[p] = row;
    value[p] = v;
  };
  for (const IntrinsicEdgeWeight& e : out.edges) put(e.j, e.i, -e.weight);
  for (Eigen::Index c = 0; c < nv; ++c) put(static_cast<int>(c), static_cast<int>(c), diag[c]);
  for (const IntrinsicEdgeWeight& e : out.edges) put(e.i, e.j, -e.weight);
  return out;
}

}  // namespace wish::geometry
