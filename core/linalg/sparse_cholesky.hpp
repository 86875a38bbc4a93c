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

#include <complex>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::linalg {

enum class CholeskyBackend { Cholmod, EigenSimplicial };
enum class CholmodMode { Auto, Supernodal, Simplicial };

const char* to_string(CholeskyBackend backend);

struct CholeskyOptions {
  CholeskyBackend backend = CholeskyBackend::Cholmod;
  CholmodMode cholmod_mode = CholmodMode::Auto;  // CHOLMOD only: supernodal pays off for large fill (Dirac)
  // Fill-reducing ordering given by the caller (CHOLMOD only; empty: CHOLMOD's default AMD/METIS choice). Used to
  // expand a METIS ordering of the V×V vertex graph to a blocked 2V/4V matrix without re-ordering the big graph.
  std::vector<int> permutation;
  // The caller stores the matrix already permuted by its fill-reducing, postordered ordering (e.g. the METIS
  // ordering of metis_ordering(), which is postordered, expanded to blocks): CHOLMOD analyses and factors it in its
  // natural ordering. A supernodal factorisation then reads the stored lower triangle as it is; with a given
  // ordering it builds two permuted transposed copies of the matrix on every factorize() (cholmod_factorize.c).
  // Excludes `permutation`.
  bool prepermuted = false;
};

// METIS nested-dissection ordering of a symmetric pattern (lower triangle read), through CHOLMOD; empty on failure.
std::vector<int> metis_ordering(const Eigen::SparseMatrix<double>& pattern);
// Expands an ordering of n block rows to one of n·block rows (row b·k + r for block k).
std::vector<int> expand_ordering(const std::vector<int>& perm, int block);

// Scalar: double (real symmetric) or std::complex<double> (Hermitian; the lower triangle is read).
template <class Scalar>
class SparseCholeskyT {
 public:
  using Matrix = Eigen::SparseMatrix<Scalar>;
  using Dense = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

  explicit SparseCholeskyT(CholeskyOptions options = {});
  ~SparseCholeskyT();
  SparseCholeskyT(const SparseCholeskyT&) = delete;
  SparseCholeskyT& operator=(const SparseCholeskyT&) = delete;

  // Symbolic analysis of the pattern of `a`. Returns false on failure (message() says why). A pattern equal to the
  // one already analysed keeps that analysis (a flow that calls analyze() every step pays for it once per mesh).
  bool analyze(const Matrix& a);
  // Numeric factorisation of a + shift·I. The symbolic analysis is redone only when the pattern of `a` differs from
  // the analysed one (or none was done): the comparison is O(nnz), the analysis it saves is not.
  bool factorize(const Matrix& a, double shift = 0.0);
  // x = (a + shift·I)⁻¹ b for every column of b; requires a successful factorize(). Throws std::logic_error
  // otherwise.
  Dense solve(const Dense& b) const;
  // Frees the numeric factor but keeps the symbolic analysis, so the next factorize() needs no analyze(). For
  // solvers used in turn (Dirac, then Poisson, each step): only one numeric factor is alive at a time, which is what
  // keeps a 160K-vertex Willmore map under 1 GiB (the Dirac factor alone is ~0.5 GiB there).
  void release_values();

  bool analyzed() const { return analyzed_; }
  // How many symbolic analyses this object has run (for tests of the reuse).
  long analysis_count() const { return analysis_count_; }
  bool factorized() const { return factorized_; }
  const std::string& message() const { return message_; }
  CholeskyBackend backend() const { return options_.backend; }
  // Non-zeros of the factor (after the last successful factorize), for reports.
  double factor_nonzeros() const;
  bool is_supernodal() const;
  double factor_flops() const;  // CHOLMOD's flop count of the last factorisation (0 for Eigen)

 private:
  struct Impl;
  CholeskyOptions options_;
  std::unique_ptr<Impl> impl_;
  bool analyzed_ = false;
  bool factorized_ = false;
  long analysis_count_ = 0;
  // The analysed pattern (column starts and row indices), to tell a new pattern from the same one.
  std::vector<int> pattern_outer_, pattern_inner_;
  bool same_pattern(const Matrix& a) const;
  std::string message_;
};

using SparseCholesky = SparseCholeskyT<double>;
using ComplexSparseCholesky = SparseCholeskyT<std::complex<double>>;

}  // namespace wish::linalg
