// Planar isometric energy kernels (thesis 2.3.2): per-face energy and corner
// gradients, per-vertex gather through the vertex -> corner CSR, per-face
// first inversion along a direction. The same arithmetic as
// face_isometric_energy / face_first_inversion in
// native/param/planar/isometric_energy.{h,cpp}. uv and d are #V x 2 row-major.
#pragma OPENCL EXTENSION cl_khr_fp64 : enable

inline double2 load2(__global const double* a, int i) { return (double2)(a[2 * i], a[2 * i + 1]); }
inline double cross2(double2 a, double2 b) { return a.x * b.y - a.y * b.x; }

// energy[f] = area η (INFINITY when det <= 0); corner_gradient[6f + 2k ..] the
// gradient at corner k when want_gradient.
__kernel void face_energy(const int m, __global const int* faces, __global const double* factors,
                          __global const double* area, __global const double* uv,
                          __global double* energy, __global double* corner_gradient,
                          const int want_gradient) {
  const int f = get_global_id(0);
  if (f >= m) return;
  const double p = factors[3 * f], q = factors[3 * f + 1], r = factors[3 * f + 2];
  const double2 u0 = load2(uv, faces[3 * f]);
  const double2 e1 = load2(uv, faces[3 * f + 1]) - u0, e2 = load2(uv, faces[3 * f + 2]) - u0;
  // S = [s0 s1] (columns) = [p e1, (q + r) e2 - q e1].
  const double2 s0 = p * e1, s1 = (q + r) * e2 - q * e1;
  const double det = s0.x * s1.y - s1.x * s0.y;
  if (!(det > 0.0)) {
    energy[f] = INFINITY;
    return;
  }
  const double frob = dot(s0, s0) + dot(s1, s1), inv_det2 = 1.0 / (det * det);
  energy[f] = area[f] * frob * (1.0 + inv_det2);
  if (!want_gradient) return;
  // dS = area (2(1 + det⁻²) S - 2|S|² det⁻³ cof(S)), cof columns (s1.y, -s1.x), (-s0.y, s0.x).
  const double a = area[f] * 2.0 * (1.0 + inv_det2), b = area[f] * 2.0 * frob * inv_det2 / det;
  const double2 d0 = a * s0 - b * (double2)(s1.y, -s1.x);
  const double2 d1 = a * s1 - b * (double2)(-s0.y, s0.x);
  const double2 g1 = p * d0 - q * d1, g2 = (q + r) * d1, g0 = -(g1 + g2);
  __global double* out = corner_gradient + 6 * f;
  out[0] = g0.x;
  out[1] = g0.y;
  out[2] = g1.x;
  out[3] = g1.y;
  out[4] = g2.x;
  out[5] = g2.y;
}

// gradient[v] = Σ of its corners' gradients, in CSR order.
__kernel void gather_gradient(const int n, __global const int* offsets,
                              __global const int* corners, __global const double* corner_gradient,
                              __global double* gradient) {
  const int v = get_global_id(0);
  if (v >= n) return;
  double2 s = (double2)(0.0, 0.0);
  for (int k = offsets[v]; k < offsets[v + 1]; ++k) s += load2(corner_gradient, corners[k]);
  gradient[2 * v] = s.x;
  gradient[2 * v + 1] = s.y;
}

// Smallest positive root of a t² + b t + c (c > 0), INFINITY if none.
inline double first_positive_root(double a, double b, double c) {
  const double scale = fmax(fabs(a), fmax(fabs(b), fabs(c)));
  if (scale == 0.0) return INFINITY;
  if (fabs(a) <= 1e-14 * scale) return b < 0.0 ? -c / b : INFINITY;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return INFINITY;
  const double q = -0.5 * (b + copysign(sqrt(disc), b));
  double best = INFINITY;
  const double t1 = q / a, t2 = q != 0.0 ? c / q : INFINITY;
  if (t1 > 0.0 && t1 < best) best = t1;
  if (t2 > 0.0 && t2 < best) best = t2;
  return best;
}

__kernel void face_first_inversion(const int m, __global const int* faces,
                                   __global const double* uv, __global const double* d,
                                   __global double* out) {
  const int f = get_global_id(0);
  if (f >= m) return;
  const int i0 = faces[3 * f], i1 = faces[3 * f + 1], i2 = faces[3 * f + 2];
  const double2 u0 = load2(uv, i0), d0 = load2(d, i0);
  const double2 e1 = load2(uv, i1) - u0, e2 = load2(uv, i2) - u0;
  const double2 f1 = load2(d, i1) - d0, f2 = load2(d, i2) - d0;
  out[f] = first_positive_root(cross2(f1, f2), cross2(e1, f2) + cross2(f1, e2), cross2(e1, e2));
}
