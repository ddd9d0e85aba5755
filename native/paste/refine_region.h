// Uniform Loop refinement of a region of a triangle mesh, stitched to the
// untouched rest (thesis 5.2: the paste refines the target region so the
// feature's detail has vertices to land on; DESIGN.md §4.5 step 3).
//
// The region's faces are tessellated uniformly (2^level segments per edge,
// 4^level triangles per face) with OpenSubdiv's Bfr::Tessellation; points on
// an edge are shared by the faces on both sides (same edge, same parameter),
// and faces outside the region that share an edge with it are re-triangulated
// to take that edge's new vertices, so the output has no cracks and no
// T-junctions. New vertices sit FLAT on the original faces; each vertex also
// gets its Loop limit position and normal, evaluated with Bfr on the WHOLE
// input mesh (so the limit surface is the mesh's, not the region's), and the
// caller chooses where to use which (the paste ramps from limit to flat
// towards the rim of its region).
#pragma once

#include <memory>
#include <vector>

#include "common/progress.h"
#include "mesh/tri_mesh.h"
#include "mesh/types.h"

namespace paramorph::paste {

struct RefinedRegion {
  /// All original vertices first, unchanged and in their order; then the new
  /// ones (flat positions on the original faces).
  MatrixX3d V;
  /// Faces outside the region that share no edge with it: unchanged, first, in
  /// their original order. Then each region face's 4^level triangles (region
  /// faces in ascending order), then the re-triangulated neighbours (a fan from
  /// the corner opposite the one split edge, or from a new centroid vertex
  /// when two or three of its edges are split). Counter-clockwise like F.
  MatrixX3i F;
  /// Indices into F of every face that is not an original face, ascending.
  VectorXi new_faces;
  /// Per vertex of V: the original face it lies on (-1 for an isolated input
  /// vertex) and its barycentric coordinates there (corner order of that
  /// face; V.row(i) == bary(i, k) * V_original.row(F(base_face(i), k)) summed).
  VectorXi base_face;
  MatrixX3d bary;
  /// Per vertex: Loop limit position and unit limit normal (oriented like the
  /// faces) of the whole input mesh at (base_face, bary). Boundaries are
  /// interpolated (OpenSubdiv VTX_BOUNDARY_EDGE_AND_CORNER). An isolated
  /// vertex keeps its position and gets a zero normal.
  MatrixX3d limit;
  MatrixX3d limit_normal;
  /// Per vertex: 1 when the vertex belongs to the refined region and is not on
  /// its rim (an edge between a region face and a face outside it, or a
  /// boundary edge of the mesh); 0 otherwise (all 0 when nothing is refined:
  /// level 0 or an empty region).
  VectorXi region_interior;
  /// Indices into the input F of the faces that are not kept as they were
  /// (the region and its re-triangulated neighbours), ascending: the output's
  /// first rows are exactly the input's other rows, in order.
  VectorXi replaced_faces;
};

/// Which vertices get Loop limit positions and normals (the others keep
/// limit = V and a zero normal): evaluating only where the caller needs them
/// keeps repeated refinements of a small region cheap on a large mesh.
enum class LimitAt {
  AllVertices,     ///< every vertex of the output
  RegionVertices,  ///< corners of region faces and every new vertex
  Nowhere,         ///< none
};

/// Solver object for repeated refinements of one mesh (DESIGN.md §6): the
/// mesh's topology, its validation and OpenSubdiv's topology refiner are built
/// once; each refine() then costs in proportion to the region (plus copying
/// the untouched arrays), which is what an interactive paste needs.
class RegionRefiner {
 public:
  /// V: #V by 3 positions; F: #F by 3 faces (0-based, counter-clockwise), a
  /// manifold, consistently oriented triangle mesh, open or closed.
  /// Throws InvalidInputError (malformed arrays), NonManifoldError (edges with
  /// more than two faces, vertices whose faces form several fans, inconsistent
  /// orientation), DegenerateFaceError (repeated indices or zero-area faces).
  RegionRefiner(const MatrixX3d& V, const MatrixX3i& F);
  ~RegionRefiner();
  RegionRefiner(RegionRefiner&&) noexcept;
  RegionRefiner& operator=(RegionRefiner&&) noexcept;

  /// region_faces: face indices to refine (duplicates ignored; empty: nothing
  /// refined); level: 0..8 (level 0 returns V and F unchanged). Throws
  /// InvalidInputError (an index out of range, a level outside 0..8), Cancelled.
  RefinedRegion refine(const std::vector<Index>& region_faces, int level,
                       LimitAt limit_at = LimitAt::AllVertices, Progress* progress = nullptr) const;

  /// Loop limit positions (#Q by 3) at points given as faces (#Q) and
  /// barycentric coordinates (#Q by 3, corner order of each face); normals
  /// (unit, oriented like the faces) into *normals when it is not null.
  MatrixX3d limit(const VectorXi& faces, const MatrixX3d& bary, MatrixX3d* normals = nullptr) const;

  const TriMesh& mesh() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot form: RegionRefiner(V, F).refine(region_faces, level,
/// LimitAt::AllVertices). Same arguments and errors.
RefinedRegion refine_region(const MatrixX3d& V, const MatrixX3i& F,
                            const std::vector<Index>& region_faces, int level,
                            Progress* progress = nullptr);

}  // namespace paramorph::paste
