// Self-intersecting faces through CGAL (mesh/self_intersections.h).
#include "mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <array>
#include <iterator>
#include <vector>

#include "common/errors.h"

namespace paramorph {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using FaceHandle = SurfaceMesh::Face_index;
}  // namespace

SelfIntersections self_intersections(const MatrixX3d& V, const MatrixX3i& F) {
  const Index n = Index(V.rows()), m = Index(F.rows());
  PM_REQUIRE(V.allFinite(), InvalidInputError, "the positions must be finite");
  PM_REQUIRE(m == 0 || (F.minCoeff() >= 0 && F.maxCoeff() < n), InvalidInputError,
             "a face has a vertex index outside [0, ", n, ")");
  SelfIntersections out;
  out.intersecting.assign(m, 0);

  // The soup: faces with a repeated vertex are left out (they are degenerate
  // and have no orientation); soup face k is mesh face `face_of[k]`.
  std::vector<Point> points;
  points.reserve(n);
  for (Index v = 0; v < n; ++v) points.emplace_back(V(v, 0), V(v, 1), V(v, 2));
  std::vector<std::array<std::size_t, 3>> soup;
  std::vector<Index> face_of;
  for (Index f = 0; f < m; ++f) {
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0)) {
      ++out.degenerate_faces;
      continue;
    }
    soup.push_back({std::size_t(F(f, 0)), std::size_t(F(f, 1)), std::size_t(F(f, 2))});
    face_of.push_back(f);
  }
  if (soup.empty()) return out;
  // A non-manifold vertex or edge is cut apart (the faces keep their order).
  if (!CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(soup))
    CGAL::Polygon_mesh_processing::orient_polygon_soup(points, soup);
  SurfaceMesh mesh;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, soup, mesh);
  PM_REQUIRE(Index(mesh.number_of_faces()) == Index(soup.size()), ComputeError,
             "the self-intersection test lost faces building its mesh (", mesh.number_of_faces(), " of ",
             soup.size(), ")");

  std::vector<std::pair<FaceHandle, FaceHandle>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
  for (const auto& [f, g] : pairs) {
    if (f == g) {  // CGAL's report of a zero-area face
      ++out.degenerate_faces;
      continue;
    }
    ++out.pairs;
    out.intersecting[face_of[std::size_t(f)]] = 1;
    out.intersecting[face_of[std::size_t(g)]] = 1;
  }
  for (char c : out.intersecting) out.intersecting_faces += c;
  return out;
}

}  // namespace paramorph
