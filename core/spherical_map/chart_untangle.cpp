#include "core/spherical_map/chart_untangle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/Geometry>

#include "core/spherical_map/map_verification.hpp"

namespace wish::spherical {
namespace {

// χ(D, ε) = (D + √(ε² + D²)) / 2, in the cancellation-free form for D < 0 (ε may be tiny there).
double chi(double d, double eps) {
  const double s = std::sqrt(eps * eps + d * d);
  return d >= 0 ? 0.5 * (d + s) : 0.5 * eps * eps / (s - d);
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Stereographic chart centred at c: rotate c to the north pole, project from the south pole.
struct Chart {
  Eigen::Vector3d e1, e2, c;
  explicit Chart(const Eigen::Vector3d& centre) : c(centre.normalized()) {
    const Eigen::Vector3d helper = std::abs(c.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    e1 = helper.cross(c).normalized();
    e2 = c.cross(e1);  // (e1, e2, c) right-handed: CCW seen from outside the sphere is CCW in the chart
  }
  Eigen::Vector2d to_chart(const Eigen::Vector3d& u) const {
    return Eigen::Vector2d(u.dot(e1), u.dot(e2)) / (1.0 + u.dot(c));
  }
  Eigen::Vector3d to_sphere(const Eigen::Vector2d& p) const {
    const double r2 = p.squaredNorm();
    return ((2 * p.x()) * e1 + (2 * p.y()) * e2 + (1 - r2) * c) / (1 + r2);
  }
};

// One triangle of the energy: its chart vertices (local indices), and B: vec(J) = B · (x0, x1, x2) with
// J = [x1 − x0, x2 − x0] · R⁻¹ (R: reference edge matrix), vec row-major (j00, j01, j10, j11).
struct Element {
  int v[3];
  Eigen::Matrix<double, 4, 6> b;
};

Element make_element(const int v[3], const Eigen::Matrix2d& ref_inverse) {
  Element e;
  for (int k = 0; k < 3; ++k) e.v[k] = v[k];
  e.b.setZero();
  const Eigen::RowVector2d r0 = ref_inverse.row(0), r1 = ref_inverse.row(1);
  const Eigen::RowVector2d w[3] = {-(r0 + r1), r0, r1};
  for (int corner = 0; corner < 3; ++corner)
    for (int i = 0; i < 2; ++i)
      for (int k = 0; k < 2; ++k) e.b(2 * i + k, 2 * corner + i) = w[corner](k);
  return e;
}

// f_ε(J) = ‖J‖² / χ(det J, ε) with gradient and PSD-projected Hessian in vec(J) (projected Newton: the element
// Hessian's negative eigenvalues are clamped to 0, so the assembled system is positive semidefinite).
struct ElementTerms {
  double f;
  Eigen::Vector4d g;
  Eigen::Matrix4d h;
};

double element_energy(const Eigen::Vector4d& j, double eps) {
  return j.squaredNorm() / chi(j(0) * j(3) - j(1) * j(2), eps);
}

ElementTerms element_terms(const Eigen::Vector4d& j, double eps) {
  const double n = j.squaredNorm(), d = j(0) * j(3) - j(1) * j(2);
  const double s = std::sqrt(eps * eps + d * d), c = chi(d, eps);
  const double c1 = c / s, c2 = eps * eps / (2 * s * s * s);
  const Eigen::Vector4d gn = 2 * j, gd(j(3), -j(2), -j(1), j(0));
  Eigen::Matrix4d hd = Eigen::Matrix4d::Zero();
  hd(0, 3) = hd(3, 0) = 1;
  hd(1, 2) = hd(2, 1) = -1;
  ElementTerms t;
  t.f = n / c;
  t.g = gn / c - n * c1 / (c * c) * gd;
  const Eigen::Matrix4d h = (2 / c) * Eigen::Matrix4d::Identity() - (c1 / (c * c)) * (gn * gd.transpose() + gd * gn.transpose()) +
                            n * (2 * c1 * c1 / (c * c * c) - c2 / (c * c)) * gd * gd.transpose() - n * c1 / (c * c) * hd;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> es(0.5 * (h + h.transpose()));
  t.h = es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).asDiagonal() * es.eigenvectors().transpose();
  return t;
}

// Projected-Newton minimisation of Σ_t f_ε(J_t) over the free vertices (local indices < free_count) of a cluster:
// a collective move (the obtuse vertex of a sliver AND its long edge's ends) that vertex-by-vertex relaxation does not
// find when each single move would invert a neighbour.
class ClusterSolver {
 public:
  ClusterSolver(std::vector<Eigen::Vector2d> x, std::vector<Element> elements, int free_count)
      : x_(std::move(x)), elements_(std::move(elements)), free_(free_count) {}

  const std::vector<Eigen::Vector2d>& positions() const { return x_; }

  double energy(double eps) const { return energy_at(x_, eps); }
  double min_det() const {
    double d = std::numeric_limits<double>::infinity();
    for (const Element& t : elements_) {
      const Eigen::Vector4d j = jac(x_, t);
      d = std::min(d, j(0) * j(3) - j(1) * j(2));
    }
    return d;
  }

  // One Newton step with backtracking line search; false when no decrease was found.
  bool newton_step(double eps) {
    const Eigen::Index n = 2 * free_;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(elements_.size() * 36);
    for (const Element& t : elements_) {
      const ElementTerms terms = element_terms(jac(x_, t), eps);
      const Eigen::Matrix<double, 6, 1> g6 = t.b.transpose() * terms.g;
      const Eigen::Matrix<double, 6, 6> h6 = t.b.transpose() * terms.h * t.b;
      for (int a = 0; a < 6; ++a) {
        const int va = t.v[a / 2];
        if (va >= free_) continue;
        g(2 * va + a % 2) += g6(a);
        for (int b = 0; b < 6; ++b) {
          const int vb = t.v[b / 2];
          if (vb < free_) triplets.emplace_back(2 * va + a % 2, 2 * vb + b % 2, h6(a, b));
        }
      }
    }
    if (!g.allFinite()) return false;
    Eigen::SparseMatrix<double> h(n, n);
    h.setFromTriplets(triplets.begin(), triplets.end());
    // Small Tikhonov term relative to the diagonal: the projected Hessian may be singular.
    double diag = 0;
    for (Eigen::Index i = 0; i < n; ++i) diag = std::max(diag, h.coeff(i, i));
    Eigen::SparseMatrix<double> id(n, n);
    id.setIdentity();
    h += (1e-9 * std::max(diag, 1e-300)) * id;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(h);
    if (ldlt.info() != Eigen::Success) return false;
    const Eigen::VectorXd step = ldlt.solve(-g);
    if (!step.allFinite()) return false;
    const double e0 = energy(eps);
    std::vector<Eigen::Vector2d> trial = x_;
    for (double alpha = 1.0; alpha > 1e-10; alpha *= 0.5) {
      for (int v = 0; v < free_; ++v) trial[static_cast<size_t>(v)] = x_[static_cast<size_t>(v)] + alpha * step.segment<2>(2 * v);
      if (energy_at(trial, eps) < e0) {
        x_.swap(trial);
        return true;
      }
    }
    return false;
  }

 private:
  static Eigen::Vector4d jac(const std::vector<Eigen::Vector2d>& x, const Element& t) {
    Eigen::Matrix<double, 6, 1> p;
    for (int k = 0; k < 3; ++k) p.segment<2>(2 * k) = x[static_cast<size_t>(t.v[k])];
    return t.b * p;
  }
  double energy_at(const std::vector<Eigen::Vector2d>& x, double eps) const {
    double e = 0;
    for (const Element& t : elements_) e += element_energy(jac(x, t), eps);
    return e;
  }

  std::vector<Eigen::Vector2d> x_;
  std::vector<Element> elements_;
  int free_;
};

// Input triangle (p0, p1, p2) in its own 2D frame (columns p1 − p0, p2 − p0), or the equilateral triangle when the
// input is too thin to serve as a reference; scaled to unit area.
Eigen::Matrix2d reference_triangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                   double min_quality) {
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const double area = 0.5 * e1.cross(e2).norm();
  const double sum_sq = e1.squaredNorm() + e2.squaredNorm() + (p2 - p1).squaredNorm();
  Eigen::Matrix2d m;
  if (!(sum_sq > 0) || !(4 * std::sqrt(3.0) * area / sum_sq >= min_quality)) {
    m << 1.0, 0.5, 0.0, std::sqrt(3.0) / 2;
  } else {
    const Eigen::Vector3d x = e1.normalized(), y = e1.cross(e2).normalized().cross(x);
    m << e1.norm(), e2.dot(x), 0.0, e2.dot(y);
  }
  return m / std::sqrt(0.5 * std::abs(m.determinant()));
}

// Faces around each vertex and each vertex's neighbours (sorted).
struct Adjacency {
  std::vector<std::vector<int>> vertex_faces, neighbours;

  Adjacency(const Eigen::MatrixX3i& faces, Eigen::Index nv)
      : vertex_faces(static_cast<size_t>(nv)), neighbours(static_cast<size_t>(nv)) {
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        vertex_faces[static_cast<size_t>(faces(f, k))].push_back(static_cast<int>(f));
        neighbours[static_cast<size_t>(faces(f, k))].push_back(faces(f, (k + 1) % 3));
        neighbours[static_cast<size_t>(faces(f, k))].push_back(faces(f, (k + 2) % 3));
      }
    for (auto& n : neighbours) {
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
    }
  }

  // Adds `rings` rings of neighbours to `set` (membership in `in`).
  void grow(std::vector<int>& set, std::vector<char>& in, int rings) const {
    for (int r = 0; r < rings; ++r) {
      const std::vector<int> current = set;
      for (int v : current)
        for (int w : neighbours[static_cast<size_t>(v)])
          if (!in[static_cast<size_t>(w)]) {
            in[static_cast<size_t>(w)] = 1;
            set.push_back(w);
          }
    }
  }
};

// Clusters: connected components of (bad faces' vertices + `rings` rings).
std::vector<std::vector<int>> find_clusters(const std::vector<Eigen::Index>& bad, const Eigen::MatrixX3i& faces,
                                            const Adjacency& adjacency, int rings, Eigen::Index nv) {
  std::vector<char> covered(static_cast<size_t>(nv), 0);
  std::vector<int> region;
  for (Eigen::Index f : bad)
    for (int k = 0; k < 3; ++k)
      if (!covered[static_cast<size_t>(faces(f, k))]) {
        covered[static_cast<size_t>(faces(f, k))] = 1;
        region.push_back(faces(f, k));
      }
  adjacency.grow(region, covered, rings);
  std::vector<int> component(static_cast<size_t>(nv), -1);
  std::vector<std::vector<int>> clusters;
  for (int start : region) {
    if (component[static_cast<size_t>(start)] >= 0) continue;
    const int id = static_cast<int>(clusters.size());
    clusters.emplace_back();
    std::vector<int> stack{start};
    component[static_cast<size_t>(start)] = id;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      clusters.back().push_back(v);
      for (int w : adjacency.neighbours[static_cast<size_t>(v)])
        if (covered[static_cast<size_t>(w)] && component[static_cast<size_t>(w)] < 0) {
          component[static_cast<size_t>(w)] = id;
          stack.push_back(w);
        }
    }
  }
  return clusters;
}

// One cluster's problem in its chart: the faces touching the cluster, the chart positions of their vertices (free
// first, then fixed) and the energy's elements.
struct ClusterProblem {
  Chart chart;
  std::vector<int> touched;
  std::vector<Eigen::Vector2d> x;
  std::vector<Element> elements;
};

// The problem of `cluster`, or nothing when the cluster cannot be charted (no centre, too wide a chart, a scale
// that is zero or not finite). `local`: a V-sized scratch of −1s, left as found.
std::optional<ClusterProblem> chart_problem(const std::vector<int>& cluster, const Eigen::MatrixX3d& sphere,
                                            const Eigen::MatrixX3d& input_vertices, const Eigen::MatrixX3i& faces,
                                            const Adjacency& adjacency, const ChartUntangleOptions& options,
                                            std::vector<int>& local) {
  // Chart centre and extent.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v : cluster) centre += sphere.row(v).transpose();
  if (!(centre.norm() > 0)) return std::nullopt;
  centre.normalize();
  // Faces touching the cluster, their vertices (free first, then fixed), local indices.
  std::vector<int> touched;
  for (int v : cluster)
    for (int f : adjacency.vertex_faces[static_cast<size_t>(v)]) touched.push_back(f);
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  std::vector<int> vertices = cluster;
  for (size_t i = 0; i < vertices.size(); ++i) local[static_cast<size_t>(vertices[i])] = static_cast<int>(i);
  for (int f : touched)
    for (int k = 0; k < 3; ++k)
      if (local[static_cast<size_t>(faces(f, k))] < 0) {
        local[static_cast<size_t>(faces(f, k))] = static_cast<int>(vertices.size());
        vertices.push_back(faces(f, k));
      }
  double max_angle = 0;
  for (int v : vertices) max_angle = std::max(max_angle, std::acos(std::clamp(sphere.row(v).dot(centre), -1.0, 1.0)));
  ClusterProblem problem{Chart(centre), std::move(touched), {}, {}};
  problem.x.resize(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) problem.x[i] = problem.chart.to_chart(sphere.row(vertices[i]).transpose());
  // Local scale of the chart (conformal maps compress by orders of magnitude across a cluster on a thin part):
  // each reference triangle gets the mean |chart area| of the faces around its vertices, so det J ≈ 1 for an
  // unflipped face wherever it is, and ε (relative to det J) means the same everywhere.
  std::vector<double> area_sum(vertices.size(), 0.0), area_count(vertices.size(), 0.0);
  for (int f : problem.touched) {
    const size_t a = static_cast<size_t>(local[static_cast<size_t>(faces(f, 0))]),
                 b = static_cast<size_t>(local[static_cast<size_t>(faces(f, 1))]),
                 c = static_cast<size_t>(local[static_cast<size_t>(faces(f, 2))]);
    const double face_area = 0.5 * std::abs(cross2(problem.x[b] - problem.x[a], problem.x[c] - problem.x[a]));
    for (size_t v : {a, b, c}) {
      area_sum[v] += face_area;
      area_count[v] += 1;
    }
  }
  problem.elements.reserve(problem.touched.size());
  bool scales_ok = true;
  for (int f : problem.touched) {
    int v[3];
    double local_area = 0;
    for (int k = 0; k < 3; ++k) {
      v[k] = local[static_cast<size_t>(faces(f, k))];
      local_area += area_sum[static_cast<size_t>(v[k])] / (3 * area_count[static_cast<size_t>(v[k])]);
    }
    const double scale = std::sqrt(local_area);
    scales_ok = scales_ok && scale > 0 && std::isfinite(scale);
    const Eigen::Matrix2d ref = scale * reference_triangle(input_vertices.row(faces(f, 0)).transpose(),
                                                           input_vertices.row(faces(f, 1)).transpose(),
                                                           input_vertices.row(faces(f, 2)).transpose(),
                                                           options.min_reference_quality);
    problem.elements.push_back(make_element(v, ref.inverse()));
  }
  for (int vertex : vertices) local[static_cast<size_t>(vertex)] = -1;
  if (max_angle > options.max_chart_angle || !scales_ok) return std::nullopt;
  return problem;
}

// Minimises the cluster's energy with ε updated between steps by the rule of the paper; true (and the cluster's
// new positions written to `sphere`) when every face touching it passes the sphere tests. The caller restores
// the cluster on false. Sets budget_stopped when the budget runs out.
bool solve_cluster(ClusterProblem& problem, const std::vector<int>& cluster, Eigen::MatrixX3d& sphere,
                   const Eigen::MatrixX3i& faces, double min_height, const ChartUntangleOptions& options,
                   const CpuBudget& budget, bool& budget_stopped) {
  ClusterSolver solver(std::move(problem.x), std::move(problem.elements), static_cast<int>(cluster.size()));
  auto write_back = [&] {
    const auto& p = solver.positions();
    for (size_t i = 0; i < cluster.size(); ++i) sphere.row(cluster[i]) = problem.chart.to_sphere(p[i]).transpose();
  };
  auto cluster_good = [&] {
    for (int f : problem.touched)
      if (is_bad_sphere_face(sphere, faces, f, min_height)) return false;
    return true;
  };
  double min_det = solver.min_det();
  double eps = std::sqrt(1e-12 + 0.04 * std::pow(std::min(min_det, 0.0), 2));
  double e_prev = solver.energy(eps);
  for (int it = 0; it < options.max_iterations; ++it) {
    if ((budget_stopped = budget.expired())) return false;
    for (int s = 0; s < options.newton_steps_per_iteration; ++s)
      if (!solver.newton_step(eps)) break;
    const double e = solver.energy(eps);
    min_det = solver.min_det();
    if (min_det > 0) {
      write_back();
      if (cluster_good()) return true;
    }
    const double sigma = std::max(1.0 - e / e_prev, 0.1);
    const double mu = (1 - sigma) * chi(min_det, eps);
    eps = min_det < mu ? 2 * std::sqrt(mu * (mu - min_det)) : 1e-13;
    e_prev = solver.energy(eps);
  }
  return false;
}

}  // namespace

ChartUntangleResult untangle_in_charts(Eigen::MatrixX3d& sphere, const Eigen::MatrixX3d& input_vertices,
                                       const Eigen::MatrixX3i& faces, const MapVerificationThresholds& thresholds,
                                       const ChartUntangleOptions& options, const CpuBudget& budget) {
  ChartUntangleResult result;
  const Eigen::Index nv = sphere.rows(), nf = faces.rows();
  if (!sphere.allFinite()) return result;
  const double min_height = thresholds.degenerate_height;
  std::vector<Eigen::Index> bad;
  for (Eigen::Index f = 0; f < nf; ++f)
    if (is_bad_sphere_face(sphere, faces, f, min_height)) bad.push_back(f);
  result.bad_faces_before = result.bad_faces_after = static_cast<long>(bad.size());
  if (bad.empty() || static_cast<double>(bad.size()) > options.max_bad_fraction * static_cast<double>(nf)) return result;

  const Adjacency adjacency(faces, nv);
  std::vector<std::vector<int>> clusters = find_clusters(bad, faces, adjacency, options.rings, nv);
  result.clusters = static_cast<long>(clusters.size());
  const Eigen::MatrixX3d original = sphere;
  std::vector<int> local(static_cast<size_t>(nv), -1);
  for (std::vector<int>& cluster : clusters) {
    if (result.budget_stopped) break;
    std::vector<char> in(static_cast<size_t>(nv), 0);
    for (int v : cluster) in[static_cast<size_t>(v)] = 1;
    bool fixed = false;
    for (int attempt = 0; attempt <= options.max_grow && !fixed; ++attempt) {
      if ((result.budget_stopped = budget.expired())) break;
      if (attempt > 0) adjacency.grow(cluster, in, options.grow_rings);
      if (static_cast<int>(cluster.size()) > options.max_cluster_vertices) break;
      std::optional<ClusterProblem> problem = chart_problem(cluster, sphere, input_vertices, faces, adjacency, options, local);
      if (!problem) break;
      const Eigen::MatrixX3d saved = sphere;  // only the cluster's rows change; restored on failure
      fixed = solve_cluster(*problem, cluster, sphere, faces, min_height, options, budget, result.budget_stopped);
      if (!fixed)
        for (int v : cluster) sphere.row(v) = saved.row(v);
    }
    if (fixed) ++result.clusters_fixed;
  }
  // Whole-map recount (a fixed cluster cannot create bad faces elsewhere: only its faces changed).
  result.bad_faces_after = count_bad_sphere_faces(sphere, faces, min_height);
  for (Eigen::Index i = 0; i < nv; ++i)
    if (sphere.row(i) != original.row(i)) ++result.moved_vertices;
  return result;
}

}  // namespace wish::spherical
