// Point location on a sphere map by walking (thesis 4.4: the overlay starts
// from one located vertex and walks face to face from there): from a start
// face, step across any edge that has the point on its outer side until no
// edge does. Every side test is an exact (optionally perturbed) orientation,
// so the answer is consistent with the overlay's other decisions.
#pragma once

#include "morph/sphere_predicates.h"

namespace paramorph::morph {

/// X: #V by 3 unit vectors of a fold-free sphere map; F: #F by 3 faces,
/// counter-clockwise seen from outside (det > 0), covering the sphere once;
/// neighbors: #F by 3, the face across the edge opposite each corner
/// (face_neighbors()). ranked_vertices: the map's vertex v takes part in the
/// symbolic perturbation with rank v (map B of the overlay), else it is fixed.
/// p: the point (its rank < 0 when it is not perturbed). start_face: where the
/// walk begins; the face of a nearby point makes the walk short.
///
/// Returns a face f holding p: perturbed_orientation(corner k+1, corner k+2,
/// p) >= 0 for every corner k (> 0 whenever p or the map is perturbed, so the
/// face is unique then). The walk picks among the edges that separate p at
/// random (a remembering stochastic walk, which cannot cycle forever on a
/// triangulation that is not Delaunay); after 2 #F + 64 steps it gives up and
/// tests every face, so it always ends. Returns -1 only for a point no face
/// holds, which a map covering the sphere does not have.
Index locate_on_sphere(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3i& neighbors,
                       bool ranked_vertices, const SpherePoint& p, Index start_face);

/// Where points lie in a sphere map, for many points at once (a morph's
/// correspondence read through the maps, morph/map_distortion): each point's
/// nearest face of the inscribed polyhedron (a CGAL AABB tree) starts an
/// exact walk (locate_on_sphere, unperturbed).
struct SphereLocations {
  VectorXi face;   ///< #P: a face of the map holding each point
  MatrixX3d bary;  ///< #P by 3: its barycentric coordinates there by central projection (>= 0, sum 1)
};

/// X, F: a fold-free sphere map covering the sphere once (not checked: on
/// a folded one a point the walk cannot place gets its nearest face);
/// points: #P by 3 non-zero directions.
SphereLocations locate_on_sphere_map(const MatrixX3d& X, const MatrixX3i& F, const MatrixX3d& points);

}  // namespace paramorph::morph
