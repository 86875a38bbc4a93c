#include "core/linalg/sparse_cholesky.hpp"

#include <cholmod.h>

#include <stdexcept>

#include <Eigen/SparseCholesky>

namespace wish::linalg {

const char* to_string(CholeskyBackend backend) {
  switch (backend) {
    case CholeskyBackend::Cholmod: return "cholmod";
    case CholeskyBackend::EigenSimplicial: return "eigen-simplicial";
  }
  return "?";
}

namespace {

// A no-copy CHOLMOD view of an Eigen compressed column-major matrix; stype −1: the lower triangle is used and any
// upper-triangle entries are ignored.
cholmod_sparse view_lower(const Eigen::SparseMatrix<double>& a) {
  cholmod_sparse s{};
  s.nrow = static_cast<size_t>(a.rows());
  s.ncol = static_cast<size_t>(a.cols());
  s.nzmax = static_cast<size_t>(a.nonZeros());
  s.p = const_cast<int*>(a.outerIndexPtr());
  s.i = const_cast<int*>(a.innerIndexPtr());
  s.x = const_cast<double*>(a.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

struct SparseCholesky::Impl {
  // CHOLMOD
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  bool started = false;
  // Eigen
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::Index n = 0;

  ~Impl() {
    if (started) {
      if (factor) cholmod_free_factor(&factor, &common);
      cholmod_finish(&common);
    }
  }
};

SparseCholesky::SparseCholesky(CholeskyOptions options) : options_(options), impl_(std::make_unique<Impl>()) {
  if (options_.backend == CholeskyBackend::Cholmod) {
    cholmod_start(&impl_->common);
    impl_->started = true;
    impl_->common.print = 0;                       // report through message(), not stdout
    impl_->common.quick_return_if_not_posdef = 1;  // stop at the first non-positive pivot
    impl_->common.supernodal = options_.cholmod_mode == CholmodMode::Supernodal   ? CHOLMOD_SUPERNODAL
                               : options_.cholmod_mode == CholmodMode::Simplicial ? CHOLMOD_SIMPLICIAL
                                                                                  : CHOLMOD_AUTO;
    impl_->common.final_ll = 1;  // simplicial path: keep LLᵀ (as supernodal), so failures mean "not definite"
  }
}

SparseCholesky::~SparseCholesky() = default;

bool SparseCholesky::analyze(const Eigen::SparseMatrix<double>& a) {
  analyzed_ = factorized_ = false;
  message_.clear();
  if (a.rows() != a.cols() || !a.isCompressed()) {
    message_ = "matrix must be square and compressed";
    return false;
  }
  impl_->n = a.rows();
  if (options_.backend == CholeskyBackend::EigenSimplicial) {
    impl_->ldlt.analyzePattern(a);
  } else {
    if (impl_->factor) cholmod_free_factor(&impl_->factor, &impl_->common);
    cholmod_sparse s = view_lower(a);
    impl_->factor = cholmod_analyze(&s, &impl_->common);
    if (!impl_->factor || impl_->common.status < CHOLMOD_OK) {
      message_ = "CHOLMOD symbolic analysis failed (status " + std::to_string(impl_->common.status) + ")";
      return false;
    }
  }
  analyzed_ = true;
  return true;
}

bool SparseCholesky::factorize(const Eigen::SparseMatrix<double>& a, double shift) {
  if (!analyzed_ && !analyze(a)) return false;
  factorized_ = false;
  message_.clear();
  if (a.rows() != impl_->n) {
    message_ = "matrix size differs from the analysed pattern";
    return false;
  }
  if (options_.backend == CholeskyBackend::EigenSimplicial) {
    impl_->ldlt.setShift(shift);
    impl_->ldlt.factorize(a);
    if (impl_->ldlt.info() != Eigen::Success) {
      message_ = "Eigen SimplicialLDLT: zero pivot (matrix singular)";
      return false;
    }
    const double dmin = impl_->ldlt.vectorD().minCoeff();
    if (!(dmin > 0)) {
      message_ = "Eigen SimplicialLDLT: matrix not positive definite (min pivot " + std::to_string(dmin) + ")";
      return false;
    }
  } else {
    cholmod_sparse s = view_lower(a);
    double beta[2] = {shift, 0.0};
    const int ok = cholmod_factorize_p(&s, beta, nullptr, 0, impl_->factor, &impl_->common);
    if (!ok || impl_->common.status == CHOLMOD_NOT_POSDEF || impl_->factor->minor < impl_->factor->n ||
        impl_->common.status < CHOLMOD_OK) {
      message_ = "CHOLMOD: matrix not positive definite (failed at column " + std::to_string(impl_->factor->minor) +
                 " of " + std::to_string(impl_->factor->n) + ", status " + std::to_string(impl_->common.status) + ")";
      return false;
    }
  }
  factorized_ = true;
  return true;
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const {
  if (!factorized_) throw std::logic_error("SparseCholesky::solve without a successful factorisation");
  if (options_.backend == CholeskyBackend::EigenSimplicial) return impl_->ldlt.solve(b);
  cholmod_dense db{};
  db.nrow = static_cast<size_t>(b.rows());
  db.ncol = static_cast<size_t>(b.cols());
  db.nzmax = db.nrow * db.ncol;
  db.d = db.nrow;
  db.x = const_cast<double*>(b.data());
  db.xtype = CHOLMOD_REAL;
  db.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, impl_->factor, &db, &impl_->common);
  if (!x) throw std::runtime_error("CHOLMOD solve failed (status " + std::to_string(impl_->common.status) + ")");
  Eigen::MatrixXd out = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(x->x), b.rows(), b.cols());
  cholmod_free_dense(&x, &impl_->common);
  return out;
}

double SparseCholesky::factor_nonzeros() const {
  if (options_.backend == CholeskyBackend::EigenSimplicial)
    return factorized_ ? static_cast<double>(impl_->ldlt.matrixL().nestedExpression().nonZeros()) : 0.0;
  return impl_->started ? impl_->common.lnz : 0.0;
}

bool SparseCholesky::is_supernodal() const {
  return options_.backend == CholeskyBackend::Cholmod && impl_->factor && impl_->factor->is_super;
}

}  // namespace wish::linalg
