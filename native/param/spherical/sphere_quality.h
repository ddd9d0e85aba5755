// Quality measures of a map onto the unit sphere (thesis 3.3, Def. 3.1).
#pragma once

#include <vector>

#include "mesh/tri_mesh.h"

namespace paramorph::spherical {

/// Signed orientation of the great-circle triangle (a, b, c) seen from outside:
/// (b - a) x (c - a) · (a + b + c), i.e. 3 det[a, b, c], written with edge
/// differences so tiny triangles keep their sign in floating point.
double sphere_orientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c);

/// Faces (indices, ascending) whose image on the sphere is folded or degenerate
/// (orientation <= 0). X: #V by 3 unit vectors.
std::vector<Index> flipped_faces(const MatrixX3d& X, const MatrixX3i& F);

/// Per-face 3D area (#F).
VectorXd face_areas(const MatrixX3d& V, const MatrixX3i& F);

/// Area stretch factor per vertex (Def. 3.1): the mean over a vertex's faces
/// of (face's share of the surface area) / (its share of the mapped area),
/// mapped areas measured on the chord triangles. Large where the map shrinks
/// the surface (extremities), ~1 where it keeps area.
VectorXd area_stretch(const TriMesh& mesh, const MatrixX3d& X);

}  // namespace paramorph::spherical
