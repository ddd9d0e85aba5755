#include "morph/map_distortion.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/errors.h"
#include "mesh/vertex_normals.h"
#include "morph/point_location.h"

namespace paramorph::morph {

namespace {

double total_area(const MatrixX3d& V, const MatrixX3i& F) {
  double area = 0;
  for (Index f = 0; f < F.rows(); ++f)
    area += 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
  return area;
}

/// Two orthonormal directions spanning the plane normal to n (columns).
Eigen::Matrix<double, 3, 2> plane_basis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e1 = (axis - axis.dot(n) * n).normalized();
  Eigen::Matrix<double, 3, 2> basis;
  basis << e1, n.cross(e1);
  return basis;
}

}  // namespace

MatrixX3d carry_through_maps(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& sphere_a,
                             const MatrixX3d& sphere_b) {
  PM_REQUIRE(sphere_a.rows() == VA.rows() && (FA.size() == 0 || (FA.minCoeff() >= 0 && FA.maxCoeff() < VA.rows())),
             InvalidInputError, "carry_through_maps: one sphere point per vertex of A (", VA.rows(), "), got ",
             sphere_a.rows(), "; faces within range");
  const SphereLocations at = locate_on_sphere_map(sphere_a, FA, sphere_b);
  MatrixX3d out(sphere_b.rows(), 3);
  for (Index v = 0; v < sphere_b.rows(); ++v) {
    const auto f = FA.row(at.face[v]);
    out.row(v) = at.bary(v, 0) * VA.row(f[0]) + at.bary(v, 1) * VA.row(f[1]) + at.bary(v, 2) * VA.row(f[2]);
  }
  return out;
}

MapDistortion map_distortion(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& sphere_a,
                             const MatrixX3d& VB, const MatrixX3i& FB, const MatrixX3d& sphere_b,
                             double cap) {
  PM_REQUIRE(sphere_a.rows() == VA.rows() && sphere_b.rows() == VB.rows() && std::isfinite(cap) && cap > 0,
             InvalidInputError, "map_distortion: one sphere point per vertex of each model, cap > 0");
  const SphereLocations at = locate_on_sphere_map(sphere_a, FA, sphere_b);
  const MatrixX3d normals_a = area_weighted_vertex_normals(VA, FA);
  MatrixX3d image(VB.rows(), 3), image_normal(VB.rows(), 3);
  for (Index v = 0; v < VB.rows(); ++v) {
    const auto f = FA.row(at.face[v]);
    image.row(v) = at.bary(v, 0) * VA.row(f[0]) + at.bary(v, 1) * VA.row(f[1]) + at.bary(v, 2) * VA.row(f[2]);
    image_normal.row(v) =
        at.bary(v, 0) * normals_a.row(f[0]) + at.bary(v, 1) * normals_a.row(f[1]) + at.bary(v, 2) * normals_a.row(f[2]);
  }
  // B scaled to A's area: an isometry up to scale has s1 = s2 = 1.
  const double scale = std::sqrt(total_area(VA, FA) / std::max(total_area(VB, FB), 1e-300));

  MapDistortion out;
  out.per_face.resize(FB.rows());
  double area_sum = 0, weighted = 0, folded = 0, capped = 0;
  for (Index f = 0; f < FB.rows(); ++f) {
    const Eigen::Vector3d b0 = VB.row(FB(f, 0)), b1 = VB.row(FB(f, 1)), b2 = VB.row(FB(f, 2));
    const Eigen::Vector3d e1 = scale * (b1 - b0), e2 = scale * (b2 - b0);
    const Eigen::Vector3d nb = e1.cross(e2);
    const double area = 0.5 * nb.norm();
    if (!(area > 0)) {
      out.per_face[f] = 0;
      continue;
    }
    Eigen::Vector3d n = (image_normal.row(FB(f, 0)) + image_normal.row(FB(f, 1)) + image_normal.row(FB(f, 2))).transpose();
    const Eigen::Vector3d i0 = image.row(FB(f, 0)), i1 = image.row(FB(f, 1)), i2 = image.row(FB(f, 2));
    if (!(n.norm() > 0)) n = (i1 - i0).cross(i2 - i0);
    double energy = cap;
    bool turned = true;
    if (n.norm() > 0) {
      n.normalize();
      const Eigen::Matrix<double, 3, 2> to_b = plane_basis(nb.normalized());
      const Eigen::Matrix<double, 3, 2> to_a = plane_basis(n);
      Eigen::Matrix2d domain, range;
      domain << to_b.transpose() * e1, to_b.transpose() * e2;
      range << to_a.transpose() * (i1 - i0), to_a.transpose() * (i2 - i0);
      const Eigen::Matrix2d J = range * domain.inverse();
      turned = !(J.determinant() > 0);
      if (!turned) {
        const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(J).singularValues();
        if (s[1] > 0) energy = std::min(cap, std::pow(std::log(s[0]), 2) + std::pow(std::log(s[1]), 2));
      }
    }
    out.per_face[f] = energy;
    area_sum += area;
    weighted += area * energy;
    if (turned) folded += area;
    if (energy >= cap) capped += area;
  }
  if (area_sum > 0) {
    out.mean = weighted / area_sum;
    out.folded_share = folded / area_sum;
    out.capped_share = capped / area_sum;
  }
  return out;
}

}  // namespace paramorph::morph
