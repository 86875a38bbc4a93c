// Spherical map benchmark (not a test): time per stage and per step and the whole map for meshes of ~2.5K, 10K,
// 40K and 160K vertices, Willmore vs cMCF, CHOLMOD vs Eigen's simplicial Cholesky, with the quality figures beside
// the times. Prints the BLAS in use and its thread count, and the peak RSS after each run.
//   OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1 build/flow/bench/spherical_map_bench [--max-vertices N] [--no-eigen]
// Meshes: the nucleus nmv_nuclei/hq/nucleus-1.obj (10.8K V) if the shared data is there, and bumpy ellipsoids built
// on icospheres of level 4..7 (2562, 10242, 40962, 163842 vertices).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/map_bench_meshes.hpp"
#include "core/linalg/blas_info.hpp"
#include "core/spherical_map/spherical_map.hpp"

namespace {

using namespace wish;

double peak_rss_mib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void run(const bench::BenchMesh& c, MapMethod method, LinearSolverKind solver) {
  SphericalMapOptions o;
  o.method = method;
  o.solver = solver;
  o.fallback = false;
  const auto t0 = std::chrono::steady_clock::now();
  const SphericalMapResult r = compute_spherical_map(c.mesh, o);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const MapAttempt& a = r.attempts.front();
  double geo = 0, fac = 0, eig = 0, poi = 0, steps_time = 0;
  int accepted = 0;
  for (const FlowStepRecord& s : a.steps) {
    geo += s.geometry_seconds;
    fac += s.factor_seconds;
    eig += s.eigen_seconds;
    poi += s.poisson_seconds;
    steps_time += s.seconds;
    accepted += s.accepted ? 1 : 0;
  }
  const int n = static_cast<int>(a.steps.size());
  const double setup = total - steps_time;  // patterns, orderings, symbolic analysis, projection, Möbius, checks
  std::printf("%-22s %8ld %-8s %-8s %3d/%-3d %8.3f %8.3f | %7.3f %7.3f %7.3f %7.3f %7.3f | %5ld %6.3f %6.3f %8.1e %-13s %7.0f\n",
              c.name.c_str(), static_cast<long>(c.mesh.vertex_count()), to_string(method),
              solver == LinearSolverKind::Cholmod ? "cholmod" : "eigen", accepted, n, total,
              n > 0 ? steps_time / n : 0.0, setup, geo, fac, eig, poi, r.quality.flipped_faces, r.quality.conformal_mean,
              r.quality.conformal_p99, r.quality.roundness, to_string(r.status), peak_rss_mib());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  long max_vertices = 200000;
  bool eigen = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--max-vertices" && i + 1 < argc) max_vertices = std::atol(argv[++i]);
    if (a == "--no-eigen") eigen = false;
  }
  std::printf("BLAS: %s\n", linalg::describe_blas().c_str());
  std::printf("OPENBLAS_NUM_THREADS=%s OMP_NUM_THREADS=%s\n", std::getenv("OPENBLAS_NUM_THREADS") ? std::getenv("OPENBLAS_NUM_THREADS") : "(unset)",
              std::getenv("OMP_NUM_THREADS") ? std::getenv("OMP_NUM_THREADS") : "(unset)");
  const std::vector<bench::BenchMesh> cases = bench::map_bench_meshes(4);
  std::printf("\ntimes in seconds; step = mean per flow step; setup = everything outside the steps; stage columns are sums "
              "over the steps\n");
  std::printf("%-22s %8s %-8s %-8s %7s %8s %8s | %7s %7s %7s %7s %7s | %5s %6s %6s %8s %-13s %7s\n", "mesh", "V", "method",
              "solver", "acc/st", "total", "step", "setup", "geom", "factor", "eigen", "poisson", "flips", "Kmean", "Kp99",
              "R", "status", "RSS MiB");
  for (const bench::BenchMesh& c : cases) {
    if (c.mesh.vertex_count() > max_vertices) continue;
    run(c, MapMethod::Willmore, LinearSolverKind::Cholmod);
    run(c, MapMethod::Cmcf, LinearSolverKind::Cholmod);
    if (eigen && c.mesh.vertex_count() <= 50000) {
      run(c, MapMethod::Willmore, LinearSolverKind::EigenSimplicial);
      run(c, MapMethod::Cmcf, LinearSolverKind::EigenSimplicial);
    }
  }
  return 0;
}
