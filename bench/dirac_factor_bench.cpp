// Dirac factorisation benchmark (not a test): the one numeric factorisation that dominates a Willmore flow step
// (docs/design/spherical-map.md §4), timed under the fill-reducing orderings and CHOLMOD modes we could choose, on the same
// complex 2V×2V Hermitian matrix 𝔼(ρ) with ρ = −0.95·P(H)-like data (ρ = −0.95·H is enough: the pattern and the
// conditioning are what matter here). Prints the factor size, CHOLMOD's flop count, and analyse / factorise /
// solve times (factorise: median of 3) per configuration, for the nucleus and the bumpy icospheres.
//   OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 build/release/bench/dirac_factor_bench [--max-vertices N] [--cholmod-openmp]
#include <cholmod.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry/cotan_laplacian.hpp"
#include "core/geometry/face_geometry.hpp"
#include "core/geometry/mass_matrix.hpp"
#include "core/geometry/mean_curvature.hpp"
#include "core/geometry/vertex_normals.hpp"
#include "core/geometry/vertex_pattern.hpp"
#include "bench/map_bench_meshes.hpp"
#include "core/linalg/blas_info.hpp"
#include "core/linalg/sparse_cholesky.hpp"
#include "core/spherical_map/dirac_operator.hpp"
#include "core/spherical_map/willmore_flow.hpp"

namespace {

using namespace wish;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

enum class Ordering { MetisVertexExpanded, AmdVertexExpanded, CholmodDefault, MetisFull, NesdisVertexExpanded };
const char* name(Ordering o) {
  switch (o) {
    case Ordering::MetisVertexExpanded: return "metis(V)x2";
    case Ordering::AmdVertexExpanded: return "amd(V)x2";
    case Ordering::CholmodDefault: return "cholmod-default(2V)";
    case Ordering::MetisFull: return "metis(2V)";
    case Ordering::NesdisVertexExpanded: return "nesdis(V)x2";
  }
  return "?";
}

cholmod_sparse lower_view(const Eigen::SparseMatrix<std::complex<double>>& a, int xtype) {
  cholmod_sparse s{};
  s.nrow = static_cast<size_t>(a.rows());
  s.ncol = static_cast<size_t>(a.cols());
  s.nzmax = static_cast<size_t>(a.nonZeros());
  s.p = const_cast<int*>(a.outerIndexPtr());
  s.i = const_cast<int*>(a.innerIndexPtr());
  s.x = const_cast<std::complex<double>*>(a.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = xtype;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

// An ordering of the vertex graph expanded to the 2×2 blocks. METIS is the flow's own (linalg::metis_ordering); AMD
// and CHOLMOD's nested dissection are called here directly, being only candidates.
std::vector<int> vertex_ordering(const Eigen::SparseMatrix<double>& pattern, Ordering o) {
  if (o == Ordering::MetisVertexExpanded) return linalg::expand_ordering(linalg::metis_ordering(pattern), 2);
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse s{};
  s.nrow = s.ncol = static_cast<size_t>(pattern.rows());
  s.nzmax = static_cast<size_t>(pattern.nonZeros());
  s.p = const_cast<int*>(pattern.outerIndexPtr());
  s.i = const_cast<int*>(pattern.innerIndexPtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_PATTERN;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = s.packed = 1;
  std::vector<int> perm(static_cast<size_t>(pattern.rows()));
  if (o == Ordering::AmdVertexExpanded) {
    cholmod_amd(&s, nullptr, 0, perm.data(), &c);
  } else {
    std::vector<int> cparent(perm.size()), cmember(perm.size());
    cholmod_nested_dissection(&s, nullptr, 0, perm.data(), cparent.data(), cmember.data(), &c);
  }
  cholmod_finish(&c);
  return linalg::expand_ordering(perm, 2);
}

// relax: CHOLMOD's supernode amalgamation (nrelax[0..2], zrelax[0..2]); 0 keeps CHOLMOD's defaults (4/16/48,
// 0.8/0.1/0.05). More amalgamation = bigger dense blocks for BLAS at the price of some explicit zeros.
void run(const std::string& mesh_name, const Mesh& mesh, Ordering ordering, int supernodal, int relax = 0) {
  Eigen::MatrixX3d x = mesh.vertices;
  spherical::normalise_area_and_centre(x, mesh.faces);
  const geometry::VertexPattern vp = geometry::build_vertex_pattern(mesh.vertex_count(), mesh.faces);
  Eigen::SparseMatrix<double> lap = vp.pattern;
  const Eigen::VectorXd areas = geometry::face_areas(x, mesh.faces);
  const Eigen::MatrixX3d cot = geometry::corner_cotangents(x, mesh.faces);
  geometry::assemble_cotan_laplacian(vp, mesh.faces, cot, lap);
  const Eigen::VectorXd mass = geometry::lumped_mass(mesh.faces, areas, x.rows());
  const Eigen::VectorXd h = geometry::mean_curvature(x, lap, mass, geometry::vertex_normals(x, mesh.faces));
  const Eigen::VectorXd rho = -0.95 * (h.array() - h.mean()).matrix();
  auto pattern = spherical::build_dirac_pattern<std::complex<double>>(vp);
  const double mean_diag = spherical::assemble_dirac(vp, pattern, x, mesh.faces, areas, rho);

  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  c.supernodal = supernodal;
  c.final_ll = 1;
  c.quick_return_if_not_posdef = 1;
  if (relax > 0) {
    c.nrelax[0] = static_cast<size_t>(relax);
    c.nrelax[1] = static_cast<size_t>(4 * relax);
    c.nrelax[2] = static_cast<size_t>(12 * relax);
    c.zrelax[0] = 0.8;
    c.zrelax[1] = 0.2;
    c.zrelax[2] = 0.1;
  }
  Clock::time_point t0 = Clock::now();
  std::vector<int> perm;
  if (ordering == Ordering::MetisFull) {
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_METIS;
  } else if (ordering != Ordering::CholmodDefault) {
    perm = vertex_ordering(vp.pattern, ordering);
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
    c.postorder = 1;
  }
  cholmod_sparse s = lower_view(pattern.matrix, CHOLMOD_COMPLEX);
  cholmod_factor* f = perm.empty() ? cholmod_analyze(&s, &c) : cholmod_analyze_p(&s, perm.data(), nullptr, 0, &c);
  const double t_analyse = seconds_since(t0);
  std::vector<double> times;
  double beta[2] = {1e-8 * mean_diag, 0.0};
  bool ok = true;
  for (int rep = 0; rep < 3; ++rep) {
    t0 = Clock::now();
    ok = cholmod_factorize_p(&s, beta, nullptr, 0, f, &c) && c.status == CHOLMOD_OK;
    times.push_back(seconds_since(t0));
  }
  std::sort(times.begin(), times.end());
  Eigen::VectorXcd b = Eigen::VectorXcd::Ones(pattern.matrix.rows());
  cholmod_dense db{};
  db.nrow = db.nzmax = db.d = static_cast<size_t>(b.size());
  db.ncol = 1;
  db.x = b.data();
  db.xtype = CHOLMOD_COMPLEX;
  db.dtype = CHOLMOD_DOUBLE;
  t0 = Clock::now();
  cholmod_dense* sol = cholmod_solve(CHOLMOD_A, f, &db, &c);
  const double t_solve = seconds_since(t0);
  cholmod_free_dense(&sol, &c);
  const std::string label = std::string(name(ordering)) + (relax > 0 ? " relax" + std::to_string(relax) : "");
  std::printf("%-16s %7ld %-26s %-10s %9.2f %9.0f %8.3f %8.3f %8.4f %6.1f %8.0f %s\n", mesh_name.c_str(),
              static_cast<long>(mesh.vertex_count()), label.c_str(), f->is_super ? "supernodal" : "simplicial",
              c.lnz / 1e6, c.fl / 1e6, t_analyse, times[1], t_solve, c.fl / times[1] / 1e9,
              static_cast<double>(c.memory_usage) / (1024.0 * 1024.0), ok ? "ok" : "FAILED");
  std::fflush(stdout);
  cholmod_free_factor(&f, &c);
  cholmod_finish(&c);
}

}  // namespace

int main(int argc, char** argv) {
  long max_vertices = 200000;
  bool cholmod_openmp = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--max-vertices" && i + 1 < argc) max_vertices = std::atol(argv[++i]);
    if (a == "--cholmod-openmp") cholmod_openmp = true;
  }
  // As core/linalg/sparse_cholesky.cpp does around every CHOLMOD call: CHOLMOD 3's own OpenMP regions stay serial
  // (they ask for num_threads(4), which only dyn-var can override); pass --cholmod-openmp to see what that costs.
  if (!cholmod_openmp) {
    omp_set_dynamic(1);
    omp_set_num_threads(1);
  }
  std::printf("BLAS: %s; CHOLMOD's OpenMP regions: %s\n", linalg::describe_blas().c_str(),
              cholmod_openmp ? "as compiled (4 threads on large supernodes)" : "serial");
  const std::vector<bench::BenchMesh> cases = bench::map_bench_meshes(5);
  std::printf("complex 2V x 2V Hermitian Dirac matrix; lnz = factor entries (millions), flops = CHOLMOD's count "
              "(millions); factorise = median of 3; peak = CHOLMOD's own peak allocation\n");
  std::printf("%-16s %7s %-26s %-10s %9s %9s %8s %8s %8s %6s %8s\n", "mesh", "V", "ordering", "mode", "lnz M", "Mflop",
              "analyse", "factor", "solve", "GF/s", "peak MiB");
  for (const auto& [mesh_name, mesh] : cases) {
    if (mesh.vertex_count() > max_vertices) continue;
    for (Ordering o : {Ordering::MetisVertexExpanded, Ordering::NesdisVertexExpanded, Ordering::AmdVertexExpanded,
                       Ordering::MetisFull, Ordering::CholmodDefault})
      run(mesh_name, mesh, o, CHOLMOD_SUPERNODAL);
    for (int relax : {8, 16, 32}) run(mesh_name, mesh, Ordering::MetisVertexExpanded, CHOLMOD_SUPERNODAL, relax);
    run(mesh_name, mesh, Ordering::MetisVertexExpanded, CHOLMOD_SIMPLICIAL);
  }
  return 0;
}
