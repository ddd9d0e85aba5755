// Work-group sums of a double array: each group writes one partial sum.
#pragma OPENCL EXTENSION cl_khr_fp64 : enable

__kernel void partial_sums(const int n, __global const double* values, __global double* partials,
                           __local double* scratch) {
  const int lid = get_local_id(0);
  const int size = get_local_size(0);
  // Each work-item first adds a strided run, so few groups cover any n.
  double s = 0.0;
  for (int i = get_global_id(0); i < n; i += get_global_size(0)) s += values[i];
  scratch[lid] = s;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int stride = size / 2; stride > 0; stride /= 2) {
    if (lid < stride) scratch[lid] += scratch[lid + stride];
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) partials[get_group_id(0)] = scratch[0];
}

// Work-group minima of a double array (INFINITY for an empty share).
__kernel void partial_mins(const int n, __global const double* values, __global double* partials,
                           __local double* scratch) {
  const int lid = get_local_id(0);
  const int size = get_local_size(0);
  double s = INFINITY;
  for (int i = get_global_id(0); i < n; i += get_global_size(0)) s = fmin(s, values[i]);
  scratch[lid] = s;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int stride = size / 2; stride > 0; stride /= 2) {
    if (lid < stride) scratch[lid] = fmin(scratch[lid], scratch[lid + stride]);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) partials[get_group_id(0)] = scratch[0];
}
