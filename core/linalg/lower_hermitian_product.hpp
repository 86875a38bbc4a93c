#pragma once
// y = A·x for a Hermitian (real: symmetric) A of which only the lower triangle is read, the convention of CHOLMOD's
// stype −1 and of the Dirac storage (dirac_operator.hpp): an entry (r, c) with r > c stands for itself and for its
// conjugate at (c, r); entries with r < c are ignored. Storing one triangle halves the memory of the largest matrix
// of a Willmore step.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace wish::linalg {

template <class Scalar>
Eigen::Matrix<Scalar, Eigen::Dynamic, 1> lower_hermitian_times(const Eigen::SparseMatrix<Scalar>& a,
                                                               const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& x) {
  Eigen::Matrix<Scalar, Eigen::Dynamic, 1> y = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Zero(a.rows());
  for (Eigen::Index c = 0; c < a.outerSize(); ++c) {
    for (typename Eigen::SparseMatrix<Scalar>::InnerIterator it(a, c); it; ++it) {
      const Eigen::Index r = it.row();
      if (r < c) continue;
      y[r] += it.value() * x[c];
      if (r > c) y[c] += Eigen::numext::conj(it.value()) * x[r];
    }
  }
  return y;
}

}  // namespace wish::linalg
