// A step of a mesh's vertices that turns no face over (mesh/step_without_turning.h).
#include "mesh/step_without_turning.h"

#include <vector>

#include "mesh/vertex_normals.h"

namespace paramorph {

MatrixX3d step_without_turning(const MatrixX3d& from, const MatrixX3d& from_normals, const MatrixX3d& move,
                               const MatrixX3i& F, int halvings, VectorXd* shares) {
  const MatrixX3d& before = from_normals;
  // Halving only around the faces that turn, so one tight spot does not
  // slow the whole mesh.
  VectorXd share = VectorXd::Ones(from.rows());
  MatrixX3d next;
  for (int halving = 0;; ++halving) {
    next = from + share.asDiagonal() * move;
    std::vector<Index> turned_faces;
    for (Index f = 0; f < Index(F.rows()); ++f)
      if (before.row(f).squaredNorm() > 0 && face_normal(next, F, f).dot(before.row(f)) <= 0)
        turned_faces.push_back(f);
    if (turned_faces.empty()) break;
    for (const Index f : turned_faces)
      for (int k = 0; k < 3; ++k) share(F(f, k)) = halving < halvings ? 0.5 * share(F(f, k)) : 0.0;
  }
  if (shares) *shares = share;
  return next;
}

}  // namespace paramorph
