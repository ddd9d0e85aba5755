# CMake toolchain for the manylinux_2_28 build (scripts/manylinux/build.sh):
# zig's clang and libc++ for glibc 2.28 (toolchain/zig), every library from
# the static prefix PARAMORPH_MANYLINUX_PREFIX (scripts/manylinux/deps), the
# header-only ones (CGAL, Boost, OpenCL headers) from the build machine.
# The module then needs nothing but libc, libm, libpthread and libdl, and
# exports only PyInit_* (module.map): its static OpenBLAS, libomp and
# libc++ stay its own inside a Blender that has others.
set(_manylinux ${CMAKE_CURRENT_LIST_DIR})
set(_prefix $ENV{PARAMORPH_MANYLINUX_PREFIX})
if(NOT _prefix OR NOT EXISTS ${_prefix}/lib/libcholmod.a)
  message(FATAL_ERROR "PARAMORPH_MANYLINUX_PREFIX must name a built prefix (scripts/manylinux/build.sh)")
endif()
set(CMAKE_C_COMPILER ${_manylinux}/toolchain/cc)
set(CMAKE_CXX_COMPILER ${_manylinux}/toolchain/c++)
set(CMAKE_AR ${_manylinux}/toolchain/ar CACHE FILEPATH "zig ar")
set(CMAKE_RANLIB ${_manylinux}/toolchain/ranlib CACHE FILEPATH "zig ranlib")
list(PREPEND CMAKE_PREFIX_PATH ${_prefix})
set(CGAL_DIR /usr/lib/x86_64-linux-gnu/cmake/CGAL CACHE PATH "Debian's CGAL (header-only)")
set(OpenCL_LIBRARY ${_prefix}/lib/libOpenCL.a CACHE FILEPATH "the dlopen stub (deps/opencl.sh)")
set(OpenCL_INCLUDE_DIR ${_prefix}/sysinc CACHE PATH "Khronos headers")
set(OpenMP_CXX_FLAGS -fopenmp CACHE STRING "")
set(OpenMP_CXX_LIB_NAMES omp CACHE STRING "")
set(OpenMP_omp_LIBRARY ${_prefix}/lib/libomp.a CACHE FILEPATH "LLVM's libomp, static")
# Boost 1.74's container_hash uses std::unary_function, which libc++ drops in C++17.
set(CMAKE_CXX_FLAGS_INIT
    "-I${_prefix}/shim -isystem ${_prefix}/include -D_LIBCPP_ENABLE_CXX17_REMOVED_UNARY_BINARY_FUNCTION")
# The static archives CHOLMOD and CGAL pull in, at the end of every link.
set(_lib ${_prefix}/lib)
set(CMAKE_CXX_STANDARD_LIBRARIES
    "-Wl,--start-group ${_lib}/libmpfr.a ${_lib}/libgmp.a ${_lib}/libcholmod.a ${_lib}/libccolamd.a ${_lib}/libcamd.a ${_lib}/libcolamd.a ${_lib}/libamd.a ${_lib}/libsuitesparseconfig.a ${_lib}/libmetis.a ${_lib}/libopenblas.a ${_lib}/libomp.a -Wl,--end-group -lm -lpthread -ldl"
    CACHE STRING "static dependencies")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "-Wl,--version-script=${_manylinux}/module.map")
