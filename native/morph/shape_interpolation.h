// In-betweens that keep shapes whole (issue 17; DESIGN.md §4.4 step 4):
// as-rigid-as-possible shape interpolation (Alexa et al. 2000) in its
// gradient-domain form (Xu et al. 2005), besides the thesis' linear one (4.4).
//
// Both ends are meshes on one topology (the merged mesh's source and target,
// or a source and the target sampled at its vertices). Per face, J is the
// deformation gradient taking the face at t = 0 to the face at t = 1 (its
// two edges and its normal scaled by the square root of twice its area, so a
// uniform scale is a multiple of a rotation), and G the whole shape's best
// rotation. At time t every face asks for its edges at t = 0 mapped by
//     J(t) = G(t) · R̄(t) · ((1 − t) I + t Q) · ((1 − t) + t σ) · exp(t log(S / σ)),
// Q S the polar decomposition of R̄ᵀ G⁻¹ J and σ = det(S)^(1/3): Q is what
// turn is left to the face beyond its neighbourhood's, mixed straight; the
// stretch's uniform scale σ goes straight (a scaled copy grows as straight
// lines grow it) and its shape S / σ by its logarithm, so that the face's
// area and volume share move monotonically from one end's to the other's
// (where S is not positive definite, the face turned over between the ends,
// (1 − t) I + t R̄ᵀ G⁻¹ J instead);
// G(t), R̄(t) turned by t of their angle (a face's angle is taken on the side
// of its neighbours' where it is near π), and the positions are the
// least-squares fit of all faces' edges: one solve with a factor computed
// once for all t. (Stretch mixed straight, as (1 − t) I + t R̄ᵀ G⁻¹ J, swells
// a face stretched one way and squeezed the other half way: a CAD box onto
// a cow was 21 % above both ends' volume at t = 1/2, a two-boss part onto a
// horse 8 %; with S's shape by its logarithm 8 % and 0 %.)
//
// R̄ is the rotation of the face's neighbourhood, not the face's own (the best
// rotation of the summed edge covariances over a few rings of faces). A
// merged mesh's faces are pieces of a face of A and one of B, and their own
// gradients turn and shear from piece to piece with both tessellations'
// facets (median 32° on a horse onto a re-tessellated copy of itself):
// interpolating those per face shrank the shape in between (the horse 17 %
// lower at t = 1/2). With R̄ the faces of a neighbourhood ask for consistent
// edges, so the in-between is the straight one seen from frames that turn
// with the parts: limbs turn instead of shortening.
//
// Thin pieces can still turn over in between (their apex crossing their base
// under that straight mix). Faces turned against both ends at t are repaired
// locally: their vertices and a ring around them are fitted again, the rest
// held, with each face asking for its own rotation R and stretch S (polar
// decomposition of G⁻¹J), S(t) = exp(t log S): a face alone never degenerates
// under that wish. A thin piece still turned over then has its apex mirrored
// back over its base, within the plane across the normal it wants (a move
// of twice its height, invisible), where that turns fewer faces over
// (measured on a horse onto a re-tessellated copy: 0.16-0.22 % of faces
// turned over after the refits, 0.013-0.025 % after the mirroring). What is
// still turned over then (faces whose normals at the ends point apart, where
// the neighbourhood turns them the long way round) has single vertices moved
// to the nearest point where every face around them has its side along an
// end's normal, small moves before larger ones (spot onto a horse, t = 1/2:
// 0.23 % turned over before, 0.05 % after).
//
// The fit's matrix is the edge graph's Laplacian (each face's edges weighted
// by the inverse of its size), not the cotangent one, so zero-area faces of a
// merged mesh cannot make it indefinite; a face of (nearly) zero area at
// either end has no reliable J and asks for its edges turned by G(t) and
// interpolated straight, with a small weight. The fit keeps each connected
// part's vertex mean on the straight line between the ends (the local repairs
// then move a few vertices). At t = 0 and t = 1 the fit is exact: every face
// asks for its own edges.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <utility>
#include <vector>

#include "common/progress.h"
#include "mesh/types.h"

namespace paramorph::morph {

class ShapeInterpolation {
 public:
  /// source, target: #V by 3 positions of one mesh at t = 0 and t = 1; F: #F
  /// by 3 faces of it (any vertex in no face follows the straight line).
  /// InvalidInputError for mismatched sizes, indices out of range or
  /// non-finite positions. progress: 0..1 over the setup (a 370k-face merged
  /// mesh takes seconds); cancel throws Cancelled.
  ShapeInterpolation(const MatrixX3d& source, const MatrixX3d& target, const MatrixX3i& F,
                     Progress* progress = nullptr);
  ~ShapeInterpolation();
  ShapeInterpolation(ShapeInterpolation&&) noexcept;
  ShapeInterpolation& operator=(ShapeInterpolation&&) noexcept;

  /// The positions at time t (0: source, 1: target; any t is accepted, the
  /// rotations extrapolate).
  MatrixX3d at(double t) const;

  /// Faces whose gradient was not used (zero area at either end).
  Index degenerate_faces() const { return degenerate_; }
  /// The global rotation's angle between the ends, radians.
  double global_angle() const { return global_angle_; }

 private:
  /// Per face, what it asks for at t: R̄(t) and the straight mix (neighbourhood
  /// = true), or its own R(t) S(t).
  Eigen::Matrix3d wish(Index f, double t, bool neighbourhood) const;
  /// factor_ of H (consumed), reporting to `progress` while it runs.
  void factor(Eigen::SparseMatrix<double>& H, Progress* progress);
  /// Per face, the unit normals of the ends carried to t by the global
  /// rotation, and the ends' own: a face is turned over at t when its normal
  /// is against both of either pair. Against the ends' own normals alone, a
  /// shape turning by nearly half a turn as a whole has every face near a
  /// right angle from both ends at t = 1/2 and any local turn counts: the
  /// repairs then bent sound faces through others (a horse onto a cow turned
  /// 150 degrees: 8 faces passing through others at t = 1/2 became 1353).
  /// Against the carried ones alone, faces turned locally past a right
  /// angle are left against both ends' own normals (spot onto a horse, turned
  /// 113 degrees as a whole: 0.88 % of faces at t = 1/2).
  struct Sides {
    std::vector<Eigen::Vector3d> from_source, from_target;  ///< unit, carried to t
    const std::vector<Eigen::Vector3d>* source;             ///< the ends' own normals
    const std::vector<Eigen::Vector3d>* target;
    bool against_both(Index f, const Eigen::Vector3d& n) const;
  };
  Sides sides_at(double t) const;
  /// The whole fit of every face's wish.
  MatrixX3d fit(double t) const;
  /// Refits the vertices of faces turned over at t (and `rings` rings around
  /// them) to the faces' own wishes, the rest held; kept only when fewer
  /// faces are turned over after, and fewer turned over and passing through
  /// others around the moved vertices together. Returns the faces still
  /// turned over.
  Index repair(double t, int rings, const Sides& sides, MatrixX3d& X) const;
  /// Face f of X is turned over at t (a degenerate face never is).
  bool is_turned(Index f, const MatrixX3d& X, const Sides& sides) const;
  std::vector<Index> turned_over(const MatrixX3d& X, const Sides& sides) const;
  /// Faces around vertex v turned over in X.
  Index turned_around(Index v, const MatrixX3d& X, const Sides& sides) const;
  /// Faces passing through others among the `moved` faces (per face: 1 or
  /// 0) and a ring around them, at `before` and at `after`.
  std::pair<Index, Index> crossing_faces(const MatrixX3d& before, const MatrixX3d& after,
                                         const std::vector<char>& moved) const;
  /// A face still turned over at t whose apex lies a hair over its base (a
  /// thin piece) has the apex mirrored back over the base, within the plane
  /// across the normal the face wants, where that turns fewer faces around
  /// the apex over. Returns the faces mended.
  Index mirror_apexes(double t, const Sides& sides, MatrixX3d& X) const;
  /// The unit normal face f should have a positive side along at t: its
  /// neighbourhood's wish, or the nearer end's normal where that wish is
  /// against both ends. Zero where the wish has no normal.
  Eigen::Vector3d wanted_side(Index f, double t, const Sides& sides) const;
  /// A vertex of a face still turned over at t moves to the nearest point
  /// where every face around it has a positive side along an end's normal of
  /// each pair (a turned face: the end nearer the side it wants, given a
  /// small height; the others: the end they keep, no thinner than they
  /// are), where that is within `reach` times the longest side around and
  /// turns fewer faces over. Returns the faces mended.
  Index untangle_vertices(double t, double reach, const Sides& sides, MatrixX3d& X) const;

  MatrixX3d source_, target_;
  MatrixX3i F_;
  Eigen::Vector3d global_log_;                 ///< G's axis times angle
  std::vector<char> face_degenerate_;
  std::vector<double> face_weight_;            ///< per face: its edges' weight in the fit
  std::vector<Eigen::Vector3d> area_log_;      ///< per face: R̄'s axis times angle
  std::vector<Eigen::Matrix3d> area_rest_;     ///< per face: R̄ᵀ G⁻¹ J
  std::vector<Eigen::Matrix3d> rest_turn_;     ///< per face: Q of R̄ᵀ G⁻¹ J = Q S (polar)
  std::vector<Eigen::Matrix3d> rest_axes_;     ///< per face: that S's eigenvectors
  std::vector<Eigen::Vector3d> rest_log_stretch_;  ///< per face: logarithms of that S's eigenvalues
  std::vector<char> rest_straight_;            ///< per face: that S not positive definite, mixed straight
  std::vector<Eigen::Vector3d> own_log_;       ///< per face: R's axis times angle
  std::vector<Eigen::Matrix3d> own_axes_;      ///< per face: S's eigenvectors
  std::vector<Eigen::Vector3d> own_log_stretch_;  ///< per face: logarithms of S's eigenvalues
  std::vector<char> own_straight_;             ///< per face: S not positive definite, mixed straight
  std::vector<Eigen::Vector3d> normal0_, normal1_;  ///< per face: its normal at the ends
  std::vector<Index> vertex_face_start_, vertex_faces_;  ///< faces around each vertex (CSR)
  VectorXi component_;        ///< per vertex: its connected part
  VectorXi anchor_of_;        ///< per part: the vertex held at 0 in the solve
  VectorXi unknown_;          ///< per vertex: its row in the solve, -1 for anchors and loose vertices
  struct Factor;              ///< the fit's sparse Cholesky factor (Eigen + METIS, kept out of this header)
  std::shared_ptr<Factor> factor_;  // shared: a cancelled setup leaves it to the thread factoring it
  Index degenerate_ = 0;
  double global_angle_ = 0;
};

}  // namespace paramorph::morph
