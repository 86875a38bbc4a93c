// SH fit: time and accuracy for Lmax 5..40 at ~10K points — direct (quadrature Gram), direct (product Gram),
// banded (k_s = 100), and numpy.linalg.lstsq (bench/sh_fit_numpy.py) on the same points, weights and basis.
//
//   OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 build/sh/bench/sh_fit_bench [--no-numpy] [--lmax 5,10,...]
//
// Shape: an ellipsoid (1.3, 1, 0.7) with an exponential bump over icosphere level 5 (10,242 vertices), the
// icosphere directions as its sphere map, area weights, nu = 1e-5. Accuracy: the objective
//   J(C) = sum_i w_i |Y_i C - X_i|^2 + nu sum_j l_j^2 (l_j+1)^2 |C_j|^2
// that every solver minimises (lower is better; reported relative to the best of the solvers), the RMS fit error,
// and the coefficient difference to numpy. Times: best of 3 runs (numpy: of lstsq alone).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/mesh/icosphere.hpp"
#include "core/sh/sh_basis.hpp"
#include "core/sh/sh_fit.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double objective(const Eigen::MatrixXd& Y, const Eigen::MatrixX3d& X, const Eigen::VectorXd& w,
                 const Eigen::VectorXd& r, double nu, const Eigen::MatrixX3d& C) {
  const Eigen::MatrixXd res = Y * C - X;
  return (res.rowwise().squaredNorm().array() * w.array()).sum() + nu * (C.rowwise().squaredNorm().array() * r.array()).sum();
}

template <class F>
double best_time(F&& f, int runs = 3) {
  double best = 1e300;
  for (int i = 0; i < runs; ++i) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return best;
}

void write_bin(const std::filesystem::path& p, const double* data, size_t count) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count * sizeof(double)));
}

}  // namespace

int main(int argc, char** argv) {
  bool numpy = true;
  std::vector<int> lmaxes = {5, 10, 15, 20, 25, 40};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--no-numpy") numpy = false;
    if (a == "--lmax" && i + 1 < argc) {
      lmaxes.clear();
      std::stringstream ss(argv[++i]);
      std::string t;
      while (std::getline(ss, t, ',')) lmaxes.push_back(std::stoi(t));
    }
  }
  const std::filesystem::path script = std::filesystem::path(__FILE__).parent_path() / "sh_fit_numpy.py";

  wish::Mesh mesh = wish::make_icosphere(5);
  const Eigen::MatrixX3d sphere = mesh.vertices;
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i) {
    const Eigen::Vector3d u = sphere.row(i);
    const double r = 1.0 + 0.2 * std::exp(3.0 * (u.dot(Eigen::Vector3d(0.3, -0.5, 0.8).normalized()) - 1.0));
    mesh.vertices.row(i) = (Eigen::Vector3d(1.3, 1.0, 0.7).asDiagonal() * (r * u)).transpose();
  }
  const Eigen::VectorXd w = wish::fit_weights(mesh, wish::FitWeighting::Area);
  const double nu = 1e-5;
  const Eigen::Index n = mesh.vertex_count();
  std::printf("SH fit benchmark: n = %ld points, area weights, nu = %g, OMP_NUM_THREADS=%s\n", long(n), nu,
              std::getenv("OMP_NUM_THREADS") ? std::getenv("OMP_NUM_THREADS") : "(unset)");
  std::printf("times in ms (best of 3); dJ = J/J_best - 1 (J: the regularised objective, lower is better); "
              "rms = RMS fit error\n\n");
  std::printf("%4s %5s | %9s %9s %9s | %9s %9s %9s | %9s %9s %9s | %9s %9s %9s %9s\n", "L", "k", "quad ms",
              "dJ", "rms", "prod ms", "dJ", "rms", "band ms", "dJ", "rms", "numpy ms", "dJ", "rms", "|dC|/|C|");
  const auto tmp = std::filesystem::temp_directory_path() / ("wish_sh_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  for (int L : lmaxes) {
    const int k = wish::sh_count(L);
    wish::ShFitOptions o;
    o.lmax = L;
    o.regularization = nu;
    const Eigen::MatrixXd Y = wish::ShBasis::get(L)->real_matrix(sphere);
    Eigen::VectorXd r(k);
    for (int j = 0; j < k; ++j) {
      const double l = wish::sh_degree(j);
      r[j] = l * l * (l + 1) * (l + 1);
    }
    auto rms_of = [&](const Eigen::MatrixX3d& C) {
      return std::sqrt((Y * C - mesh.vertices).rowwise().squaredNorm().mean());
    };
    Eigen::MatrixX3d cq, cp, cb, cn;
    wish::fit_real_sh(sphere, mesh.vertices, w, o);  // warm the per-Lmax caches
    const double tq = best_time([&] { cq = wish::fit_real_sh(sphere, mesh.vertices, w, o); });
    double tp = NAN;
    if (L <= 25) {
      o.gram = wish::GramMethod::Product;
      tp = best_time([&] { cp = wish::fit_real_sh(sphere, mesh.vertices, w, o); }, L <= 15 ? 3 : 1);
      o.gram = wish::GramMethod::Quadrature;
    }
    o.solver = wish::FitSolver::Banded;
    const double tb = best_time([&] { cb = wish::fit_real_sh(sphere, mesh.vertices, w, o); });
    double tn = NAN;
    if (numpy) {
      write_bin(tmp / "Y.bin", Y.data(), size_t(Y.size()));
      write_bin(tmp / "X.bin", mesh.vertices.data(), size_t(mesh.vertices.size()));
      write_bin(tmp / "w.bin", w.data(), size_t(n));
      write_bin(tmp / "r.bin", r.data(), size_t(k));
      const std::string cmd = "/usr/bin/python3 " + script.string() + " " + tmp.string() + " " + std::to_string(n) +
                              " " + std::to_string(k) + " " + std::to_string(nu) + " > " + (tmp / "out.txt").string();
      if (std::system(cmd.c_str()) == 0) {
        std::ifstream in(tmp / "out.txt");
        in >> tn;
        cn.resize(k, 3);
        std::ifstream cin(tmp / "C.bin", std::ios::binary);
        cin.read(reinterpret_cast<char*>(cn.data()), std::streamsize(sizeof(double) * 3 * k));
      } else {
        numpy = false;
        std::printf("(numpy run failed; continuing without)\n");
      }
    }
    const double jq = objective(Y, mesh.vertices, w, r, nu, cq);
    const double jb = objective(Y, mesh.vertices, w, r, nu, cb);
    const double jp = cp.size() ? objective(Y, mesh.vertices, w, r, nu, cp) : NAN;
    const double jn = cn.size() ? objective(Y, mesh.vertices, w, r, nu, cn) : NAN;
    double jbest = std::min(jq, jb);
    if (!std::isnan(jp)) jbest = std::min(jbest, jp);
    if (!std::isnan(jn)) jbest = std::min(jbest, jn);
    auto d = [&](double j) { return j / jbest - 1; };
    std::printf("%4d %5d | %9.2f %9.1e %9.3e | %9.2f %9.1e %9.3e | %9.2f %9.1e %9.3e | %9.2f %9.1e %9.3e %9.1e\n", L,
                k, 1e3 * tq, d(jq), rms_of(cq), 1e3 * tp, d(jp), cp.size() ? rms_of(cp) : NAN, 1e3 * tb, d(jb),
                rms_of(cb), 1e3 * tn, d(jn), cn.size() ? rms_of(cn) : NAN,
                cn.size() ? (cq - cn).norm() / cq.norm() : NAN);
    std::fflush(stdout);
  }
  std::filesystem::remove_all(tmp);
  return 0;
}
