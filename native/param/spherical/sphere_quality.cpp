#include "param/spherical/sphere_quality.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/errors.h"
#include "common/parallel.h"

namespace paramorph::spherical {

double sphere_orientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  return (b - a).cross(c - a).dot(a + b + c);
}

std::vector<Index> flipped_faces(const MatrixX3d& X, const MatrixX3i& F) {
  const Index m = Index(F.rows());
  std::vector<char> bad(m, 0);
#pragma omp parallel for schedule(static) if (worth_parallel(m))
  for (Index f = 0; f < m; ++f) {
    bad[f] = sphere_orientation(X.row(F(f, 0)), X.row(F(f, 1)), X.row(F(f, 2))) <= 0.0;
  }
  std::vector<Index> out;
  for (Index f = 0; f < m; ++f)
    if (bad[f]) out.push_back(f);
  return out;
}

VectorXd face_areas(const MatrixX3d& V, const MatrixX3i& F) {
  const Index m = Index(F.rows());
  VectorXd A(m);
#pragma omp parallel for schedule(static) if (worth_parallel(m))
  for (Index f = 0; f < m; ++f) {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    A[f] = 0.5 * (b - a).cross(c - a).norm();
  }
  return A;
}

VectorXd area_stretch(const TriMesh& mesh, const MatrixX3d& X) {
  const VectorXd surface = face_areas(mesh.V(), mesh.F());
  const VectorXd mapped = face_areas(X, mesh.F());
  const double surface_total = surface.sum();
  const double mapped_total = mapped.sum();
  PM_REQUIRE(X.rows() == mesh.num_vertices() && X.allFinite(), InvalidInputError,
             "the sphere positions must be finite, one row per vertex");
  PM_REQUIRE(std::isfinite(surface_total) && surface_total > 0, InvalidInputError,
             "the mesh's area is ", surface_total == 0 ? "zero" : "not finite (coordinates too large: scale the mesh)",
             ": area stretch compares each face's share of it");
  PM_REQUIRE(std::isfinite(mapped_total) && mapped_total > 0, InvalidInputError,
             "the mapped surface's area is zero or not finite: give the sphere map's positions");
  const Index m = mesh.num_faces();
  VectorXd face_stretch(m);
  for (Index f = 0; f < m; ++f) {
    const double share = mapped[f] / mapped_total;
    face_stretch[f] = share > 0 ? (surface[f] / surface_total) / share
                                : std::numeric_limits<double>::infinity();
  }
  const Csr& corners = mesh.vertex_corners();
  VectorXd out(mesh.num_vertices());
#pragma omp parallel for schedule(static) if (worth_parallel(mesh.num_vertices()))
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    double sum = 0.0;
    for (Index k = corners.begin(v); k < corners.end(v); ++k) sum += face_stretch[corners.items[k] / 3];
    out[v] = corners.size(v) > 0 ? sum / corners.size(v) : 0.0;
  }
  return out;
}

}  // namespace paramorph::spherical
