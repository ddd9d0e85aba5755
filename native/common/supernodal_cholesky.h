// CHOLMOD's supernodal Cholesky (Eigen::CholmodSupernodalLLT) with its
// numeric factorisation and its solves under the process-wide BLAS lock
// (common/library_locks.h): the dense fronts go through BLAS, which is not safe
// to call from two threads at once with every BLAS a system may load. The
// symbolic analysis (orderings, no BLAS) runs unlocked.
#pragma once

#include <Eigen/CholmodSupport>
#include <mutex>

#include "common/library_locks.h"

namespace paramorph {

template <typename SparseMatrix>
class SupernodalCholesky {
 public:
  using Factor = Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>;

  SupernodalCholesky() = default;
  explicit SupernodalCholesky(const SparseMatrix& A) { compute(A); }

  /// CHOLMOD's settings (orderings, printing), to set before analyze().
  cholmod_common& cholmod() { return factor_.cholmod(); }

  /// The symbolic factorisation of A's pattern (lower triangle used).
  void analyze(const SparseMatrix& A) {
    const std::lock_guard<std::mutex> lock(metis_lock());
    factor_.analyzePattern(A);
  }

  /// The numeric factorisation of A, whose pattern analyze() saw.
  void factorize(const SparseMatrix& A) {
    const std::lock_guard<std::mutex> lock(blas_lock());
    factor_.factorize(A);
  }

  void compute(const SparseMatrix& A) {
    analyze(A);
    factorize(A);
  }

  Eigen::ComputationInfo info() const { return factor_.info(); }
  Eigen::Index rows() const { return factor_.rows(); }

  /// A⁻¹ B, evaluated under the lock (CHOLMOD also writes its workspace
  /// here, so one solve at a time per factor as well).
  template <typename Rhs>
  typename Rhs::PlainObject solve(const Eigen::MatrixBase<Rhs>& B) const {
    const std::lock_guard<std::mutex> lock(blas_lock());
    return factor_.solve(B);
  }

 private:
  Factor factor_;
};

}  // namespace paramorph
