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

namespace paramorph {

constexpr Index kParallelMinimum = 8192;

constexpr bool worth_parallel(Index items) { return items >= kParallelMinimum; }

}  // namespace paramorph
