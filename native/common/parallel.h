// When a loop is worth an OpenMP parallel region.
//
// A region costs a fork and a join. Where the cores are busy with other work
// (a shared machine, Blender drawing, a CI run), a thread descheduled at the
// join stalls the others for a time slice, and loops run once per sweep or
// iteration pay that thousands of times: a 1.7k-face isometric map went from
// 14 ms to 2.5 s, and a 320-face sphere map (20,000 relaxation sweeps) from
// 0.33 s to 2-7 s, on a 2-core machine with six other busy processes. Below
// kParallelMinimum items the loops run on one thread: `#pragma omp parallel
// for ... if (worth_parallel(n))`. Results do not depend on it (the loops
// write per item, and sums are taken in a fixed order). Loops run once per
// call with heavy items (point location, concavity) keep their threads.
#pragma once

#include "mesh/types.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace paramorph {

constexpr Index kParallelMinimum = 8192;

constexpr bool worth_parallel(Index items) { return items >= kParallelMinimum; }

/// Lets OpenMP run fewer threads when other processes keep the cores busy
/// (dynamic adjustment: libgomp takes the load average into account), for
/// the calling thread's parallel regions. Measured with two busy processes
/// on a 2-core machine (sphere_map, medians of 5): a 70k-face bunny 1.66 s
/// with both threads, 1.01 s adjusted, 1.21 s on one thread; a 112k-face
/// star 5.9 / 5.1 / 4.9 s; quiet, all three alike (0.56-0.65 s, 2.3-2.4 s).
/// The bindings call it before every long call (python/progress.h).
inline void adapt_threads_to_load() {
#ifdef _OPENMP
  omp_set_dynamic(1);
#endif
}

}  // namespace paramorph
