#include "mesh/reorder.h"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "common/morton.h"

namespace paramorph {

Reordering locality_order(const MatrixX3d& V, const MatrixX3i& F) {
  const Index n = Index(V.rows()), m = Index(F.rows());
  Reordering r;
  std::vector<std::uint64_t> code(n, 0);
  if (n > 0) {
    const Eigen::RowVector3d lo = V.colwise().minCoeff();
    const Eigen::RowVector3d extent = (V.colwise().maxCoeff() - lo).cwiseMax(1e-300);
    const double cells = double((1 << 21) - 1);
    for (Index i = 0; i < n; ++i) {
      std::uint64_t cell[3];
      for (int d = 0; d < 3; ++d)
        cell[d] = std::uint64_t(std::clamp((V(i, d) - lo[d]) / extent[d], 0.0, 1.0) * cells);
      code[i] = morton_code(cell[0], cell[1], cell[2]);
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
