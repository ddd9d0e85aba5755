// The process-wide library locks (see library_locks.h).
#include "common/library_locks.h"

namespace paramorph {

std::mutex& blas_lock() {
  static std::mutex lock;
  return lock;
}

std::mutex& metis_lock() {
  static std::mutex lock;
  return lock;
}

}  // namespace paramorph
