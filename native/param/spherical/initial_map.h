// Fold-free starting maps onto the unit sphere (thesis 4.3.2; DESIGN.md §4.2).
//
// stereographic_tutte_map: puncture the mesh at one vertex, embed the rest in
// the plane with the spring weights and its 1-ring on a circle (Tutte/Floater:
// positive weights + convex boundary => no folds), then lift to the sphere by
// inverse stereographic projection with the punctured vertex at the pole. One
// sparse Cholesky solve instead of thousands of relaxation sweeps.
//
// centroid_relaxation: the thesis' area-weighted centroid relaxation; used to
// repair the few folds the lift can create in large triangles, and as the
// thesis' own start (init="relaxation").
//
// mobius_center: Möbius balancing, moving the area-weighted centroid of the
// map to the origin so no region starts collapsed.
#pragma once

#include <Eigen/SparseCholesky>
#include <memory>
#include <vector>

#include "common/fill_reducing_ordering.h"
#include "common/progress.h"
#include "mesh/tri_mesh.h"
#include "param/spherical/spring_graph.h"

namespace paramorph::spherical {

/// The spring Laplacian with Dirichlet conditions on a puncture vertex and its
/// 1-ring, factored once (sparse Cholesky, METIS ordering). It gives the Tutte
/// embedding and, reused, the PCG preconditioner of the outer loop.
struct PuncturedLaplacian {
  using Factor = Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                                      FillReducingOrdering<int>>;
  Index puncture = -1;
  std::vector<Index> ring;             ///< 1-ring of the puncture, in face orientation order
  std::vector<Index> interior_index;   ///< #V: row in the factor, or -1 (puncture and ring)
  Index interior_count = 0;
  std::unique_ptr<Factor> factor;      ///< L_II over the interior vertices
};

/// `puncture`: the vertex sent to the pole, or -1 to pick the vertex with the
/// largest 1-ring area. Expects a validated closed genus-0 mesh.
std::shared_ptr<const PuncturedLaplacian> factor_punctured_laplacian(const TriMesh& mesh,
                                                                     const SpringGraph& graph,
                                                                     Index puncture = -1);

/// #V by 3 unit vectors: Tutte embedding of the punctured mesh (ring on a
/// circle spaced by edge length), lifted by inverse stereographic projection.
MatrixX3d stereographic_tutte_map(const TriMesh& mesh, const SpringGraph& graph,
                                  const PuncturedLaplacian& laplacian);

/// Centered, normalised input coordinates (4.7): v_i / |v_i| after moving the
/// area centroid to the origin.
MatrixX3d radial_projection(const TriMesh& mesh);

/// Area-weighted centroid relaxation sweeps (4.3.2) on X (in place) until no
/// face is folded, or `max_sweeps`. Returns the sweeps run. Faces are checked
/// every `check_every` sweeps.
int centroid_relaxation(const TriMesh& mesh, MatrixX3d& X, int max_sweeps,
                        int check_every = 10, ProgressWindow progress = {});

/// Möbius balancing (in place): repeatedly applies the ball automorphism that
/// sends the `vertex_weights`-weighted centroid to the origin, until its norm
/// is below `tolerance` or a step would fold a face. Returns the final norm.
double mobius_center(MatrixX3d& X, const MatrixX3i& F, const VectorXd& vertex_weights,
                     int max_steps = 50, double tolerance = 1e-8);

/// One third of the incident 3D face areas per vertex (#V).
VectorXd vertex_areas(const TriMesh& mesh);

}  // namespace paramorph::spherical
