#pragma once
// Sparse Cholesky factorisation of a symmetric positive definite matrix whose sparsity pattern stays fixed while its
// values change (one flow step after another): the symbolic analysis (fill-reducing ordering, elimination tree,
// supernodes) is done once by analyze(), each factorize() is numeric only.
//
// Backends: CHOLMOD (SuiteSparse; supernodal LLᵀ on BLAS for large fill, simplicial otherwise) and Eigen's
// SimplicialLDLT (AMD ordering; no BLAS). Both factor A + shift·I without copying A.
//
// Failure is a return value, never a silent NaN: factorize() returns false when A + shift·I is not numerically
// positive definite (CHOLMOD: a non-positive pivot, Eigen: a non-positive entry of D) or on any other solver error,
// and message() says which. A matrix with a kernel (e.g. the cot Laplacian) must be made definite by the caller
// (pin a vertex, or add a small multiple of the mass) — factorize() refuses to pretend.
//
// Input matrices: square, compressed column-major, both triangles stored or only the lower one (the lower triangle
// is what is read). Not thread-safe per object; separate objects may be used from separate threads.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::linalg {

enum class CholeskyBackend { Cholmod, EigenSimplicial };
enum class CholmodMode { Auto, Supernodal, Simplicial };

const char* to_string(CholeskyBackend backend);

struct CholeskyOptions {
  CholeskyBackend backend = CholeskyBackend::Cholmod;
  CholmodMode cholmod_mode = CholmodMode::Auto;  // CHOLMOD only: supernodal pays off for large fill (Dirac 4V×4V)
};

class SparseCholesky {
 public:
  explicit SparseCholesky(CholeskyOptions options = {});
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Symbolic analysis of the pattern of `a`. Returns false on failure (message() says why).
  bool analyze(const Eigen::SparseMatrix<double>& a);
  // Numeric factorisation of a + shift·I; `a` must have the pattern given to analyze() (analyzes first if none).
  bool factorize(const Eigen::SparseMatrix<double>& a, double shift = 0.0);
  // x = (a + shift·I)⁻¹ b for every column of b; requires a successful factorize(). Throws std::logic_error
  // otherwise.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;

  bool analyzed() const { return analyzed_; }
  bool factorized() const { return factorized_; }
  const std::string& message() const { return message_; }
  CholeskyBackend backend() const { return options_.backend; }
  // Non-zeros of the factor (after the last successful factorize), for reports.
  double factor_nonzeros() const;
  bool is_supernodal() const;

 private:
  struct Impl;
  CholeskyOptions options_;
  std::unique_ptr<Impl> impl_;
  bool analyzed_ = false;
  bool factorized_ = false;
  std::string message_;
};

}  // namespace wish::linalg
