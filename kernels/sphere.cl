// Spherical parameterization kernels (thesis 3.3.1 Algorithm 3, 3.4).
// One work-item per vertex or per face; the same arithmetic as
// native/param/spherical/sphere_kernels_cpu.cpp. Vectors are #V x 3 row-major.
#pragma OPENCL EXTENSION cl_khr_fp64 : enable

inline double3 load3(__global const double* a, int i) {
  return (double3)(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
}
inline void store3(__global double* a, int i, double3 v) {
  a[3 * i] = v.x;
  a[3 * i + 1] = v.y;
  a[3 * i + 2] = v.z;
}

// Weighted sum of the 1-ring of vertex i.
inline double3 ring_sum(int i, __global const int* offsets, __global const int* neighbors,
                        __global const double* weights, __global const double* u) {
  double3 s = (double3)(0.0, 0.0, 0.0);
  for (int k = offsets[i]; k < offsets[i + 1]; ++k) s += weights[k] * load3(u, neighbors[k]);
  return s;
}

// Algorithm 3, one damped Jacobi sweep with the per-vertex multiplier.
__kernel void jacobi_sweep(const int n, __global const int* offsets, __global const int* neighbors,
                           __global const double* weights, __global const double* degree,
                           __global const double* x, __global const double* u_in,
                           __global double* u_out, const double omega) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const double3 xi = load3(x, i);
  const double3 avg = ring_sum(i, offsets, neighbors, weights, u_in);
  const double3 t = (1.0 - omega) * load3(u_in, i) + (omega / degree[i]) * avg;
  const double lambda = dot(xi, t) - 1.0;
  store3(u_out, i, t - lambda * xi);
}

// |Π_i (u_i - sum_j w_ij u_j / D_i)|^2 per vertex.
__kernel void residual_terms(const int n, __global const int* offsets,
                             __global const int* neighbors, __global const double* weights,
                             __global const double* degree, __global const double* x,
                             __global const double* u, __global double* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const double3 xi = load3(x, i);
  double3 r = load3(u, i) - ring_sum(i, offsets, neighbors, weights, u) / degree[i];
  r -= dot(xi, r) * xi;
  out[i] = dot(r, r);
}

// out_i = Π_i (L t)_i.
__kernel void projected_laplacian(const int n, __global const int* offsets,
                                  __global const int* neighbors, __global const double* weights,
                                  __global const double* degree, __global const double* x,
                                  __global const double* t, __global double* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const double3 xi = load3(x, i);
  double3 r = degree[i] * load3(t, i) - ring_sum(i, offsets, neighbors, weights, t);
  r -= dot(xi, r) * xi;
  store3(out, i, r);
}

// Half the spring energy of the edges (i, j > i) per vertex.
__kernel void energy_terms(const int n, __global const int* offsets, __global const int* neighbors,
                           __global const double* weights, __global const double* X,
                           __global double* out) {
  const int i = get_global_id(0);
  if (i >= n) return;
  const double3 xi = load3(X, i);
  double e = 0.0;
  for (int k = offsets[i]; k < offsets[i + 1]; ++k) {
    const int j = neighbors[k];
    if (j > i) {
      const double3 d = xi - load3(X, j);
      e += weights[k] * dot(d, d);
    }
  }
  out[i] = 0.5 * e;
}

// 1 where the great-circle triangle is folded or degenerate:
// (b - a) x (c - a) · (a + b + c) <= 0.
__kernel void flipped_flags(const int m, __global const int* faces, __global const double* X,
                            __global double* out) {
  const int f = get_global_id(0);
  if (f >= m) return;
  const double3 a = load3(X, faces[3 * f]);
  const double3 b = load3(X, faces[3 * f + 1]);
  const double3 c = load3(X, faces[3 * f + 2]);
  out[f] = dot(cross(b - a, c - a), a + b + c) <= 0.0 ? 1.0 : 0.0;
}
