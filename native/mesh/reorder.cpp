#include "mesh/reorder.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace paramorph {

namespace {

/// Spreads the low 21 bits of v so two zero bits separate each.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

}  // namespace

Reordering locality_order(const MatrixX3d& V, const MatrixX3i& F) {
  const Index n = Index(V.rows()), m = Index(F.rows());
  Reordering r;
  std::vector<std::uint64_t> code(n, 0);
  if (n > 0) {
    const Eigen::RowVector3d lo = V.colwise().minCoeff();
    const Eigen::RowVector3d extent = (V.colwise().maxCoeff() - lo).cwiseMax(1e-300);
    const double cells = double((1 << 21) - 1);
    for (Index i = 0; i < n; ++i) {
      std::uint64_t key = 0;
      for (int d = 0; d < 3; ++d) {
        const double t = (V(i, d) - lo[d]) / extent[d];
        key |= spread_bits(std::uint64_t(std::clamp(t, 0.0, 1.0) * cells)) << d;
      }
      code[i] = key;
    }
  }
  r.new_to_old_vertex.resize(n);
  std::iota(r.new_to_old_vertex.begin(), r.new_to_old_vertex.end(), 0);
  std::stable_sort(r.new_to_old_vertex.begin(), r.new_to_old_vertex.end(),
                   [&](Index a, Index b) { return code[a] < code[b]; });
  r.old_to_new_vertex.resize(n);
  for (Index i = 0; i < n; ++i) r.old_to_new_vertex[r.new_to_old_vertex[i]] = i;

  std::vector<Index> face_key(m);
  for (Index f = 0; f < m; ++f)
    face_key[f] = std::min({r.old_to_new_vertex[F(f, 0)], r.old_to_new_vertex[F(f, 1)],
                            r.old_to_new_vertex[F(f, 2)]});
  r.new_to_old_face.resize(m);
  std::iota(r.new_to_old_face.begin(), r.new_to_old_face.end(), 0);
  std::stable_sort(r.new_to_old_face.begin(), r.new_to_old_face.end(),
                   [&](Index a, Index b) { return face_key[a] < face_key[b]; });
  return r;
}

MatrixX3d Reordering::apply_to_vertices(const MatrixX3d& V) const {
  MatrixX3d out(V.rows(), 3);
  for (Index i = 0; i < Index(V.rows()); ++i) out.row(i) = V.row(new_to_old_vertex[i]);
  return out;
}

MatrixX3i Reordering::apply_to_faces(const MatrixX3i& F) const {
  MatrixX3i out(F.rows(), 3);
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k) out(f, k) = old_to_new_vertex[F(new_to_old_face[f], k)];
  return out;
}

MatrixX3d Reordering::restore_vertices(const MatrixX3d& X) const {
  MatrixX3d out(X.rows(), 3);
  for (Index i = 0; i < Index(X.rows()); ++i) out.row(new_to_old_vertex[i]) = X.row(i);
  return out;
}

VectorXd Reordering::restore_vector(const VectorXd& x) const {
  VectorXd out(x.size());
  for (Index i = 0; i < Index(x.size()); ++i) out[new_to_old_vertex[i]] = x[i];
  return out;
}

}  // namespace paramorph
