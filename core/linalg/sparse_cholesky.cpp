#include "core/linalg/sparse_cholesky.hpp"

#include <cholmod.h>
#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include <Eigen/SparseCholesky>

#include "core/common/stage_profile.hpp"
#include "core/linalg/serial_openmp.hpp"

namespace wish::linalg {

const char* to_string(CholeskyBackend backend) {
  switch (backend) {
    case CholeskyBackend::Cholmod: return "cholmod";
    case CholeskyBackend::EigenSimplicial: return "eigen-simplicial";
  }
  return "?";
}

namespace {

// CHOLMOD's large blocks (a factor's values, its workspace) on transparent huge pages. Every numeric factorisation
// writes its factor, and a fresh block is first touched one 4 KiB page fault at a time: 15 % of a nucleus map's CPU
// samples were in the page-fault handler after the factors were kept between steps (perf record). Blocks of 4 MiB and
// more are 2 MiB-aligned and advised MADV_HUGEPAGE (a hint: the kernel may ignore it, the memory is ordinary malloc
// memory either way, freed by free(), which stays CHOLMOD's free). Set once before main(), as SuiteSparse_config.h
// asks (before threads start).
constexpr size_t kHugePage = size_t{2} << 20;
constexpr size_t kHugeFrom = size_t{4} << 20;

void* cholmod_malloc(size_t bytes) {
  if (bytes < kHugeFrom) return std::malloc(bytes);
  void* p = nullptr;
  if (posix_memalign(&p, kHugePage, bytes) != 0) return nullptr;
  (void)madvise(p, bytes, MADV_HUGEPAGE);
  return p;
}

void* cholmod_calloc(size_t count, size_t size) {
  if (size != 0 && count > static_cast<size_t>(-1) / size) return nullptr;
  if (count * size < kHugeFrom) return std::calloc(count, size);
  void* p = cholmod_malloc(count * size);
  if (p) std::memset(p, 0, count * size);
  return p;
}

const bool cholmod_allocator_set = [] {
  SuiteSparse_config.malloc_func = cholmod_malloc;
  SuiteSparse_config.calloc_func = cholmod_calloc;
  return true;
}();

template <class Scalar>
constexpr int cholmod_xtype() {
  return std::is_same_v<Scalar, double> ? CHOLMOD_REAL : CHOLMOD_COMPLEX;  // complex: interleaved (re, im)
}

// CHOLMOD 3 (SuiteSparse 5) runs its supernodal scatter/clear loops as `omp parallel for num_threads(4) if (size >
// threshold)`: a clause that overrides OMP_NUM_THREADS and omp_set_num_threads(). On a 2-core machine every large
// supernode then woke 3 helper threads (per worker!) for a memory-bound loop: 40 % of a Willmore map's samples were
// thread wake-ups, and the nucleus-1 Dirac factorisation took 0.19 s instead of 0.07 s (bench/dirac_factor_bench).
// Every CHOLMOD call therefore runs inside a SerialOpenMpScope (serial_openmp.hpp): its parallel regions run inline on
// the calling thread, without the runtime's per-region system calls. Parallelism inside a factorisation comes from
// the BLAS (threads set by the caller, see blas_info.hpp), which is where the flops are.

// A no-copy CHOLMOD view of an Eigen compressed column-major matrix; stype −1: the lower triangle is used and any
// upper-triangle entries are ignored.
template <class Scalar>
cholmod_sparse view_lower(const Eigen::SparseMatrix<Scalar>& a) {
  cholmod_sparse s{};
  s.nrow = static_cast<size_t>(a.rows());
  s.ncol = static_cast<size_t>(a.cols());
  s.nzmax = static_cast<size_t>(a.nonZeros());
  s.p = const_cast<int*>(a.outerIndexPtr());
  s.i = const_cast<int*>(a.innerIndexPtr());
  s.x = const_cast<Scalar*>(a.valuePtr());
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = cholmod_xtype<Scalar>();
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

}  // namespace

std::vector<int> metis_ordering(const Eigen::SparseMatrix<double>& pattern) {
  const SerialOpenMpScope serial;
  cholmod_common c;
  cholmod_start(&c);
  c.print = 0;
  cholmod_sparse s = view_lower(pattern);
  s.xtype = CHOLMOD_PATTERN;
  std::vector<int> perm(static_cast<size_t>(pattern.rows()));
  const int ok = cholmod_metis(&s, nullptr, 0, 1, perm.data(), &c);
  cholmod_finish(&c);
  if (!ok) perm.clear();
  return perm;
}

std::vector<int> expand_ordering(const std::vector<int>& perm, int block) {
  std::vector<int> out(perm.size() * static_cast<size_t>(block));
  for (size_t k = 0; k < perm.size(); ++k)
    for (int r = 0; r < block; ++r) out[k * static_cast<size_t>(block) + static_cast<size_t>(r)] = block * perm[k] + r;
  return out;
}

template <class Scalar>
struct SparseCholeskyT<Scalar>::Impl {
  // CHOLMOD
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  bool started = false;
  // Eigen
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Scalar>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::Index n = 0;

  ~Impl() {
    if (started) {
      if (factor) cholmod_free_factor(&factor, &common);
      cholmod_finish(&common);
    }
  }
};

template <class Scalar>
SparseCholeskyT<Scalar>::SparseCholeskyT(CholeskyOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>()) {
  if (options_.backend == CholeskyBackend::Cholmod) {
    cholmod_start(&impl_->common);
    impl_->started = true;
    impl_->common.print = 0;                       // report through message(), not stdout
    impl_->common.quick_return_if_not_posdef = 1;  // stop at the first non-positive pivot
    impl_->common.supernodal = options_.cholmod_mode == CholmodMode::Supernodal   ? CHOLMOD_SUPERNODAL
                               : options_.cholmod_mode == CholmodMode::Simplicial ? CHOLMOD_SIMPLICIAL
                                                                                  : CHOLMOD_AUTO;
    impl_->common.final_ll = 1;  // simplicial path: keep LLᵀ (as supernodal), so failures mean "not definite"
    if (options_.prepermuted) {
      if (!options_.permutation.empty())
        throw std::invalid_argument("SparseCholesky: a prepermuted matrix takes no further permutation");
      impl_->common.nmethods = 1;
      impl_->common.method[0].ordering = CHOLMOD_NATURAL;
      impl_->common.postorder = 0;  // a postorder would make CHOLMOD permute the matrix again
    } else if (!options_.permutation.empty()) {
      impl_->common.nmethods = 1;
      impl_->common.method[0].ordering = CHOLMOD_GIVEN;
      impl_->common.postorder = 1;
    }
  }
}

template <class Scalar>
SparseCholeskyT<Scalar>::~SparseCholeskyT() = default;

template <class Scalar>
bool SparseCholeskyT<Scalar>::same_pattern(const Matrix& a) const {
  if (!analyzed_ || !a.isCompressed() || a.rows() != impl_->n || a.cols() != impl_->n) return false;
  const size_t outer = static_cast<size_t>(a.cols()) + 1, inner = static_cast<size_t>(a.nonZeros());
  return pattern_outer_.size() == outer && pattern_inner_.size() == inner &&
         std::equal(pattern_outer_.begin(), pattern_outer_.end(), a.outerIndexPtr()) &&
         std::equal(pattern_inner_.begin(), pattern_inner_.end(), a.innerIndexPtr());
}

template <class Scalar>
bool SparseCholeskyT<Scalar>::analyze(const Matrix& a) {
  if (same_pattern(a)) {  // the analysis would come out the same: keep it (and the factor's storage)
    factorized_ = false;
    message_.clear();
    return true;
  }
  const profile::ScopedStage stage(std::is_same_v<Scalar, double> ? "cholesky.analyze (real)" : "cholesky.analyze (complex)");
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
    const SerialOpenMpScope serial;
    if (impl_->factor) cholmod_free_factor(&impl_->factor, &impl_->common);
    cholmod_sparse s = view_lower(a);
    if (!options_.permutation.empty() && options_.permutation.size() == static_cast<size_t>(a.rows()))
      impl_->factor = cholmod_analyze_p(&s, options_.permutation.data(), nullptr, 0, &impl_->common);
    else
      impl_->factor = cholmod_analyze(&s, &impl_->common);
    if (!impl_->factor || impl_->common.status < CHOLMOD_OK) {
      message_ = "CHOLMOD symbolic analysis failed (status " + std::to_string(impl_->common.status) + ")";
      return false;
    }
  }
  analyzed_ = true;
  ++analysis_count_;
  pattern_outer_.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.cols() + 1);
  pattern_inner_.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  return true;
}

template <class Scalar>
bool SparseCholeskyT<Scalar>::factorize(const Matrix& a, double shift) {
  if (!same_pattern(a) && !analyze(a)) return false;
  const profile::ScopedStage stage(std::is_same_v<Scalar, double> ? "cholesky.factorize (real)" : "cholesky.factorize (complex)");
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
    const double dmin = impl_->ldlt.vectorD().real().minCoeff();
    if (!(dmin > 0)) {
      message_ = "Eigen SimplicialLDLT: matrix not positive definite (min pivot " + std::to_string(dmin) + ")";
      return false;
    }
  } else {
    const SerialOpenMpScope serial;
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

template <class Scalar>
typename SparseCholeskyT<Scalar>::Dense SparseCholeskyT<Scalar>::solve(const Dense& b) const {
  if (!factorized_) throw std::logic_error("SparseCholesky::solve without a successful factorisation");
  const profile::ScopedStage stage(std::is_same_v<Scalar, double> ? "cholesky.solve (real)" : "cholesky.solve (complex)");
  if (options_.backend == CholeskyBackend::EigenSimplicial) return impl_->ldlt.solve(b);
  const SerialOpenMpScope serial;
  cholmod_dense db{};
  db.nrow = static_cast<size_t>(b.rows());
  db.ncol = static_cast<size_t>(b.cols());
  db.nzmax = db.nrow * db.ncol;
  db.d = db.nrow;
  db.x = const_cast<Scalar*>(b.data());
  db.xtype = cholmod_xtype<Scalar>();
  db.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_solve(CHOLMOD_A, impl_->factor, &db, &impl_->common);
  if (!x) throw std::runtime_error("CHOLMOD solve failed (status " + std::to_string(impl_->common.status) + ")");
  Dense out = Eigen::Map<const Dense>(static_cast<const Scalar*>(x->x), b.rows(), b.cols());
  cholmod_free_dense(&x, &impl_->common);
  return out;
}

template <class Scalar>
void SparseCholeskyT<Scalar>::release_values() {
  if (!factorized_) return;
  factorized_ = false;
  // Eigen's SimplicialLDLT cannot drop its values and keep its analysis: there the factor only becomes unusable.
  if (options_.backend == CholeskyBackend::EigenSimplicial) return;
  // Back to a symbolic factor of the same kind (supernodal stays supernodal): values freed, structure kept.
  const SerialOpenMpScope serial;
  cholmod_change_factor(CHOLMOD_PATTERN, impl_->factor->is_ll, impl_->factor->is_super, 0, 0, impl_->factor,
                        &impl_->common);
}

template <class Scalar>
double SparseCholeskyT<Scalar>::factor_nonzeros() const {
  if (options_.backend == CholeskyBackend::EigenSimplicial)
    return factorized_ ? static_cast<double>(impl_->ldlt.matrixL().nestedExpression().nonZeros()) : 0.0;
  return impl_->started ? impl_->common.lnz : 0.0;
}

template <class Scalar>
double SparseCholeskyT<Scalar>::factor_flops() const {
  return options_.backend == CholeskyBackend::Cholmod && impl_->started ? impl_->common.fl : 0.0;
}

template <class Scalar>
bool SparseCholeskyT<Scalar>::is_supernodal() const {
  return options_.backend == CholeskyBackend::Cholmod && impl_->factor && impl_->factor->is_super;
}

template class SparseCholeskyT<double>;
template class SparseCholeskyT<std::complex<double>>;

}  // namespace wish::linalg
