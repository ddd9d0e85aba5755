// mesh/step_without_turning: a step of every vertex at once that turns no
// face over, halved only around the faces that would turn.
#include <gtest/gtest.h>

#include "mesh/step_without_turning.h"
#include "mesh/vertex_normals.h"
#include "test_meshes.h"

using namespace paramorph;

namespace {

int faces_turned(const MatrixX3d& before, const MatrixX3d& after, const MatrixX3i& F) {
  int turned = 0;
  for (Index f = 0; f < Index(F.rows()); ++f) turned += face_normal(after, F, f).dot(face_normal(before, F, f)) <= 0;
  return turned;
}

MatrixX3d normals_of(const MatrixX3d& V, const MatrixX3i& F) {
  MatrixX3d N(F.rows(), 3);
  for (Index f = 0; f < Index(F.rows()); ++f) N.row(f) = face_normal(V, F, f);
  return N;
}

}  // namespace

TEST(StepWithoutTurning, AFreeStepIsTakenWhole) {
  const auto [V, F] = test_meshes::icosphere(2);
  const MatrixX3d move = 0.01 * V;  // a slight inflation turns nothing
  VectorXd shares;
  const MatrixX3d next = step_without_turning(V, normals_of(V, F), move, F, 12, &shares);
  EXPECT_TRUE(next.isApprox(V + move, 0));
  EXPECT_EQ(shares.minCoeff(), 1.0);
}

TEST(StepWithoutTurning, HalvesOnlyAroundTheFacesThatWouldTurn) {
  const auto [V, F] = test_meshes::icosphere(2);
  // One vertex pushed through the sphere to the far side turns its faces
  // over; every other vertex moves a little outwards and turns nothing.
  MatrixX3d move = 0.01 * V;
  const Index pushed = 0;
  move.row(pushed) = -2.0 * V.row(pushed);
  VectorXd shares;
  const MatrixX3d next = step_without_turning(V, normals_of(V, F), move, F, 12, &shares);
  EXPECT_EQ(faces_turned(V, next, F), 0);
  EXPECT_LT(shares(pushed), 1.0);
  EXPECT_GT(shares(pushed), 0.0);  // a small enough share of its move turns nothing
  // Vertices sharing no face with the pushed one keep their whole step.
  std::vector<char> near(V.rows(), 0);
  for (Index f = 0; f < Index(F.rows()); ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) == pushed)
        for (int j = 0; j < 3; ++j) near[F(f, j)] = 1;
  int whole = 0, far = 0;
  for (Index v = 0; v < Index(V.rows()); ++v)
    if (!near[v]) {
      ++far;
      whole += shares(v) == 1.0;
    }
  EXPECT_EQ(whole, far);
}

TEST(StepWithoutTurning, WithNoHalvingsLeftTheVerticesStay) {
  const auto [V, F] = test_meshes::icosphere(2);
  MatrixX3d move = MatrixX3d::Zero(V.rows(), 3);
  move.row(0) = -2.0 * V.row(0);
  VectorXd shares;
  const MatrixX3d next = step_without_turning(V, normals_of(V, F), move, F, 0, &shares);
  EXPECT_EQ(shares(0), 0.0);
  EXPECT_TRUE(next.isApprox(V, 0));
  EXPECT_EQ(faces_turned(V, next, F), 0);
}
