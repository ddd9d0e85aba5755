// Process-wide locks around the libraries the core calls that are not safe,
// or not deterministic, when two threads call them at once. Long calls
// release the GIL, so Python threads (and a cancelled morph's factorisation
// finishing on its own thread while the next operator runs) do reach them
// together.
#pragma once

#include <mutex>

namespace paramorph {

/// Held by every call that reaches the dense BLAS: CHOLMOD's supernodal
/// factorisations and solves, and Ipopt's MUMPS. A single-threaded OpenBLAS
/// built without USE_LOCKING (Debian 12's openblas-serial, the libblas.so.3
/// the system picks by default there) shares its work buffers between the
/// threads that call it: two factorisations at once gave wrong factors and
/// "not positive definite" on a positive definite matrix. Which BLAS is
/// loaded is the system's choice, not ours.
std::mutex& blas_lock();

/// Held by every fill-reducing ordering that may call METIS (Eigen's
/// MetisOrdering, CHOLMOD's analysis). Debian's METIS draws its random
/// numbers from the C library's one rand() stream, seeded at each call:
/// two orderings at once draw from each other's stream and come out
/// different (valid, but the answers then differ from a run alone).
std::mutex& metis_lock();

}  // namespace paramorph
