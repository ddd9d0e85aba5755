// weld_vertices (mesh/weld_vertices.h): clusters within the tolerance, named
// by their lowest index; chains join; exact mode welds equal positions only.
#include <gtest/gtest.h>

#include <limits>

#include "common/errors.h"
#include "mesh/weld_vertices.h"

using namespace paramorph;

TEST(WeldVertices, JoinsVerticesWithinTheToleranceIntoTheLowestIndex) {
  MatrixX3d V(6, 3);
  V << 0, 0, 0,      //
      1, 0, 0,       //
      0, 0, 0.001,   // within 0.01 of vertex 0
      1, 0, 0.02,    // 0.02 from vertex 1: apart
      0, 0, 0.0105,  // 0.0095 from vertex 2: joins 0 through the chain
      5, 5, 5;
  const VectorXi into = weld_vertices(V, 0.01);
  EXPECT_EQ(into(0), 0);
  EXPECT_EQ(into(1), 1);
  EXPECT_EQ(into(2), 0);
  EXPECT_EQ(into(3), 3);
  EXPECT_EQ(into(4), 0);
  EXPECT_EQ(into(5), 5);
}

TEST(WeldVertices, ZeroToleranceWeldsExactlyEqualPositionsOnly) {
  MatrixX3d V(4, 3);
  V << 1, 2, 3,  //
      1, 2, 3 + 1e-15,  //
      1, 2, 3,  //
      -1, 0, 0;
  const VectorXi into = weld_vertices(V, 0.0);
  EXPECT_EQ(into(0), 0);
  EXPECT_EQ(into(1), 1);
  EXPECT_EQ(into(2), 0);
  EXPECT_EQ(into(3), 3);
}

TEST(WeldVertices, RefusesABadTolerance) {
  MatrixX3d V = MatrixX3d::Zero(2, 3);
  EXPECT_THROW(weld_vertices(V, -1.0), InvalidInputError);
  EXPECT_THROW(weld_vertices(V, std::numeric_limits<double>::quiet_NaN()), InvalidInputError);
}
