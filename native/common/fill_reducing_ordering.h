// The fill-reducing ordering of every Eigen sparse Cholesky factorization in
// the core: METIS's nested dissection (Eigen::MetisOrdering), which halves
// AMD's fill on 100k-vertex meshes, except on small matrices, where METIS 5
// can divide by zero (a tetrahedron's punctured Laplacian: SIGFPE in
// FM_2WayCutRefine, the process killed) and the fill does not matter: AMD.
#pragma once

#include <iostream>  // Eigen/MetisSupport uses std::cerr without including it
#include <Eigen/MetisSupport>
#include <Eigen/OrderingMethods>
#include <mutex>

#include "common/library_locks.h"

namespace paramorph {

/// Below this many rows the AMD ordering is used: the crashes were at 3-4
/// rows; 100 keeps METIS (and so the same factors, to the last bit) for
/// every matrix of a real mesh, the coarsest level of a balanced map
/// included (about 300 rows).
constexpr Eigen::Index kSmallestMetisOrdering = 100;

/// An Eigen ordering (the Ordering parameter of SimplicialLLT/LDLT).
template <typename StorageIndex>
class FillReducingOrdering {
 public:
  using PermutationType = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, StorageIndex>;

  template <typename MatrixType>
  void operator()(const MatrixType& A, PermutationType& permutation) {
    if (A.rows() < kSmallestMetisOrdering)
      Eigen::AMDOrdering<StorageIndex>()(A, permutation);
    else {
      const std::lock_guard<std::mutex> lock(metis_lock());  // its random numbers: library_locks.h
      Eigen::MetisOrdering<StorageIndex>()(A, permutation);
    }
  }
};

}  // namespace paramorph
