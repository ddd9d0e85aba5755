// Uniform Loop refinement of a mesh region with limit positions and normals
// (paste/refine_region.h; thesis 5.2, DESIGN.md §4.5 step 3).
#include "paste/refine_region.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <Eigen/Geometry>
#include <array>
#include <cassert>
#include <cmath>
#include <memory>
#include <type_traits>

#include "common/errors.h"
#include "mesh/tri_mesh.h"
#include "mesh/validate.h"

namespace paramorph::paste {

namespace {

namespace Bfr = OpenSubdiv::Bfr;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

static_assert(std::is_same<Index, Far::Index>::value, "F is handed to OpenSubdiv without a copy");

/// Where boundary coordinate i of the uniform triangle tessellation sits: a
/// corner (edge_from == -1) or point j (1..rate-1) of the edge from corner
/// edge_from to corner (edge_from + 1) % 3, counted from edge_from.
struct BoundarySlot {
  int corner = -1;
  int edge_from = -1;
  int j = 0;
};

/// The one tessellation every region face shares (same parameterization and rate).
struct Pattern {
  int rate = 1;
  std::vector<BoundarySlot> boundary;
  std::vector<std::array<double, 2>> interior;  ///< (u, v) of the interior coordinates
  std::vector<std::array<int, 3>> facets;       ///< coordinate indices: boundary first
};

Pattern tessellation_pattern(int rate) {
  const Bfr::Parameterization param(Sdc::SCHEME_LOOP, 3);
  Bfr::Tessellation tess(param, rate);
  Pattern p;
  p.rate = rate;
  const int nb = tess.GetNumBoundaryCoords(), ni = tess.GetNumInteriorCoords();
  std::vector<double> uv(2 * std::size_t(nb + ni));
  tess.GetCoords(uv.data());
  const double eps = 0.25 / rate;  // coordinates are multiples of 1 / rate
  p.boundary.resize(nb);
  for (int i = 0; i < nb; ++i) {
    const double u = uv[2 * i], v = uv[2 * i + 1];
    BoundarySlot& s = p.boundary[i];
    // Param corners: 0 at (0, 0), 1 at (1, 0), 2 at (0, 1).
    if (std::abs(u) < eps && std::abs(v) < eps) {
      s.corner = 0;
    } else if (std::abs(u - 1) < eps && std::abs(v) < eps) {
      s.corner = 1;
    } else if (std::abs(u) < eps && std::abs(v - 1) < eps) {
      s.corner = 2;
    } else if (std::abs(v) < eps) {
      s.edge_from = 0, s.j = int(std::lround(u * rate));
    } else if (std::abs(u + v - 1) < eps) {
      s.edge_from = 1, s.j = int(std::lround(v * rate));
    } else {
      s.edge_from = 2, s.j = int(std::lround((1 - v) * rate));
    }
  }
  for (int i = 0; i < ni; ++i) p.interior.push_back({uv[2 * (nb + i)], uv[2 * (nb + i) + 1]});
  std::vector<int> facets(3 * std::size_t(tess.GetNumFacets()));
  tess.GetFacets(facets.data());
  for (std::size_t k = 0; k < facets.size(); k += 3)
    p.facets.push_back({facets[k], facets[k + 1], facets[k + 2]});
  return p;
}

/// Throws the typed error for input OpenSubdiv cannot treat as a manifold.
void require_manifold(const TriMesh& mesh) {
  const MeshReport report = validate(mesh);
  PM_REQUIRE(report.non_manifold_edges.empty(), NonManifoldError,
             "edges with more than two faces: ",
             format_vertex_pairs(report.non_manifold_edge_vertices));
  PM_REQUIRE(report.non_manifold_vertices.empty(), NonManifoldError,
             "vertices whose faces form several fans: ",
             format_indices(report.non_manifold_vertices));
  PM_REQUIRE(report.inconsistent_orientation_edges.empty(), NonManifoldError,
             "faces not consistently oriented across edges ",
             format_vertex_pairs(report.inconsistent_orientation_edge_vertices));
  PM_REQUIRE(report.degenerate_faces.empty(), DegenerateFaceError,
             "degenerate faces (repeated indices or zero area): ",
             format_indices(report.degenerate_faces));
}

/// Loop limit position and normal of every vertex at (base_face, bary), with
/// Bfr on the whole mesh: one SurfaceFactory per thread, one Surface per face.
void evaluate_limit(const MatrixX3d& V0, const MatrixX3i& F0, RefinedRegion& out) {
  const Index n = Index(out.V.rows()), faces = Index(F0.rows());
  out.limit = out.V;
  out.limit_normal = MatrixX3d::Zero(n, 3);
  if (faces == 0) return;

  Far::TopologyDescriptor desc;
  const std::vector<int> valences(std::size_t(faces), 3);
  desc.numVertices = int(V0.rows());
  desc.numFaces = int(faces);
  desc.numVertsPerFace = valences.data();
  desc.vertIndicesPerFace = F0.data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  const std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, sdc)));
  PM_REQUIRE(refiner, NonManifoldError, "OpenSubdiv could not build the mesh's topology");

  // Vertices grouped by base face (counting sort), so each Surface is built once.
  std::vector<Index> offsets(std::size_t(faces) + 1, 0);
  std::vector<Index> order(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
    if (out.base_face(i) >= 0) ++offsets[out.base_face(i) + 1];
  for (Index f = 0; f < faces; ++f) offsets[f + 1] += offsets[f];
  {
    std::vector<Index> cursor(offsets.begin(), offsets.end() - 1);
    for (Index i = 0; i < n; ++i)
      if (out.base_face(i) >= 0) order[cursor[out.base_face(i)]++] = i;
  }

  const Bfr::Surface<double>::PointDescriptor point(3);
#pragma omp parallel
  {
    const Bfr::RefinerSurfaceFactory<> factory(*refiner);
    Bfr::Surface<double> surface;
    std::vector<double> patch;
#pragma omp for schedule(dynamic, 256)
    for (Index f = 0; f < faces; ++f) {
      if (offsets[f] == offsets[f + 1]) continue;
      const bool ok = factory.InitVertexSurface(f, &surface);
      if (ok) {
        patch.resize(3 * std::size_t(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(V0.data(), point, patch.data(), point);
      }
      const Eigen::RowVector3d a = V0.row(F0(f, 0)), b = V0.row(F0(f, 1)), c = V0.row(F0(f, 2));
      const Eigen::RowVector3d flat_normal = (b - a).cross(c - a).normalized();
      for (Index k = offsets[f]; k < offsets[f + 1]; ++k) {
        const Index i = order[k];
        // Bfr's triangle parameterization: corner 0 at (0, 0), 1 at (1, 0), 2 at (0, 1).
        const double uv[2] = {out.bary(i, 1), out.bary(i, 2)};
        Eigen::RowVector3d P, du, dv;
        if (!ok) {  // no limit surface for this face: keep it flat
          out.limit_normal.row(i) = flat_normal;
          continue;
        }
        surface.Evaluate(uv, patch.data(), point, P.data(), du.data(), dv.data());
        const Eigen::RowVector3d normal = du.cross(dv);
        out.limit.row(i) = P;
        // Du x Dv vanishes only where the parameterization degenerates; the
        // flat normal is then the best local answer.
        out.limit_normal.row(i) = normal.norm() > 1e-300 ? normal.normalized() : flat_normal;
      }
    }
  }
}

}  // namespace

RefinedRegion refine_region(const MatrixX3d& V, const MatrixX3i& F,
                            const std::vector<Index>& region_faces, int level,
                            Progress* progress) {
  validate_arrays(V, F);
  PM_REQUIRE(level >= 0 && level <= 8, InvalidInputError, "level must be in 0..8, got ", level);
  const Index nv = Index(V.rows()), nf = Index(F.rows());
  std::vector<char> in_region(std::size_t(nf), 0);
  for (const Index f : region_faces) {
    PM_REQUIRE(f >= 0 && f < nf, InvalidInputError, "region face ", f, " is out of range [0, ", nf,
               ")");
    in_region[f] = 1;
  }
  if (progress) progress->report(0.0, "refine region");
  const TriMesh mesh(V, F);
  require_manifold(mesh);
  const MatrixX2i& E = mesh.edges();
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& EF = mesh.edge_faces();
  const Index ne = Index(E.rows());

  RefinedRegion out;
  const int rate = 1 << level;
  const bool refine = level > 0 && !region_faces.empty();

  // Edges of region faces get rate - 1 points each, ordered from E(e, 0) to
  // E(e, 1); both faces of the edge use these (no cracks, no T-junctions).
  std::vector<Index> edge_first(std::size_t(ne), -1);
  std::vector<Index> edge_owner(std::size_t(ne), -1);  // a region face holding the edge
  std::vector<char> rim_edge(std::size_t(ne), 0);
  Index next = nv;
  if (refine) {
    for (Index e = 0; e < ne; ++e) {
      Index region_count = 0;
      for (Index k = EF.begin(e); k < EF.end(e); ++k)
        if (in_region[EF.items[k]]) {
          if (edge_owner[e] < 0) edge_owner[e] = EF.items[k];
          ++region_count;
        }
      if (edge_owner[e] < 0) continue;
      edge_first[e] = next;
      next += rate - 1;
      rim_edge[e] = region_count < 2;  // to a face outside, or the mesh's boundary
    }
  }

  // Faces outside the region with a split edge are re-triangulated.
  std::vector<char> neighbour(std::size_t(nf), 0);
  std::vector<Index> untouched;
  Index num_neighbours = 0, num_centroids = 0;
  for (Index f = 0; f < nf; ++f) {
    if (in_region[f] && refine) continue;
    int split = 0;
    for (int k = 0; k < 3; ++k) split += edge_first[FE(f, k)] >= 0;
    if (split == 0) {
      untouched.push_back(f);
    } else {
      neighbour[f] = char(split);
      ++num_neighbours;
      num_centroids += split >= 2;
    }
  }

  const Pattern pattern = tessellation_pattern(rate);
  const Index per_face_interior = Index(pattern.interior.size());
  Index num_region = 0;
  for (Index f = 0; f < nf; ++f) num_region += refine && in_region[f];
  const Index interior_first = next;
  next += num_region * per_face_interior;
  const Index centroid_first = next;
  next += num_centroids;
  const Index total = next;

  out.V.resize(total, 3);
  out.bary = MatrixX3d::Zero(total, 3);
  out.base_face = VectorXi::Constant(total, -1);
  out.region_interior = VectorXi::Zero(total);
  out.V.topRows(nv) = V;

  // Original vertices: a corner of their first face.
  const Csr& VC = mesh.vertex_corners();
  for (Index v = 0; v < nv; ++v) {
    if (VC.size(v) == 0) continue;
    const Index corner = VC.items[VC.begin(v)];
    out.base_face(v) = corner / 3;
    out.bary(v, corner % 3) = 1.0;
  }
  const auto place = [&](Index i, Index f, double b0, double b1, double b2) {
    out.base_face(i) = f;
    out.bary.row(i) << b0, b1, b2;
    out.V.row(i) = b0 * V.row(F(f, 0)) + b1 * V.row(F(f, 1)) + b2 * V.row(F(f, 2));
  };
  const auto corner_of = [&](Index f, Index v) {
    return F(f, 0) == v ? 0 : F(f, 1) == v ? 1 : 2;
  };

  // Edge points.
  for (Index e = 0; e < ne; ++e) {
    if (edge_first[e] < 0) continue;
    const Index f = edge_owner[e];
    const int ka = corner_of(f, E(e, 0)), kb = corner_of(f, E(e, 1));
    for (int j = 1; j < rate; ++j) {
      const double s = double(j) / rate;
      double b[3] = {0.0, 0.0, 0.0};
      b[ka] = 1.0 - s;
      b[kb] = s;
      const Index i = edge_first[e] + j - 1;
      place(i, f, b[0], b[1], b[2]);
      out.V.row(i) = (1.0 - s) * V.row(E(e, 0)) + s * V.row(E(e, 1));  // exact on the edge
    }
  }
  if (progress) progress->report(0.2, "refine region");

  // Output faces: untouched first, then region tessellations, then neighbours.
  const Index num_faces = Index(untouched.size()) + num_region * Index(pattern.facets.size()) +
                          [&] {
                            Index count = 0;
                            for (Index f = 0; f < nf; ++f)
                              if (neighbour[f] == 1) count += rate;
                              else if (neighbour[f] > 1) count += 3 + neighbour[f] * (rate - 1);
                            return count;
                          }();
  out.F.resize(num_faces, 3);
  Index row = 0;
  for (const Index f : untouched) out.F.row(row++) = F.row(f);
  const Index first_new = row;

  // The global vertex of point j of the edge from corner k to corner k+1 of f.
  const auto edge_point = [&](Index f, int k, int j) -> Index {
    const Index e = FE(f, (k + 2) % 3);
    return F(f, k) == E(e, 0) ? edge_first[e] + j - 1 : edge_first[e] + rate - 1 - j;
  };

  std::vector<Index> boundary_map(pattern.boundary.size());
  Index region_index = 0;
  for (Index f = 0; f < nf && refine; ++f) {
    if (!in_region[f]) continue;
    const Index first_interior = interior_first + region_index++ * per_face_interior;
    for (std::size_t i = 0; i < pattern.boundary.size(); ++i) {
      const BoundarySlot& s = pattern.boundary[i];
      boundary_map[i] = s.corner >= 0 ? F(f, s.corner) : edge_point(f, s.edge_from, s.j);
    }
    for (Index i = 0; i < per_face_interior; ++i) {
      const auto& uv = pattern.interior[std::size_t(i)];
      place(first_interior + i, f, 1.0 - uv[0] - uv[1], uv[0], uv[1]);
    }
    const int nb = int(pattern.boundary.size());
    for (const auto& facet : pattern.facets) {
      for (int c = 0; c < 3; ++c)
        out.F(row, c) = facet[c] < nb ? boundary_map[facet[c]] : first_interior + facet[c] - nb;
      ++row;
    }
  }

  Index centroid = centroid_first;
  std::vector<Index> loop;
  for (Index f = 0; f < nf; ++f) {
    if (!neighbour[f]) continue;
    if (neighbour[f] == 1) {
      // Fan from the corner opposite the one split edge: no extra vertex.
      int k = 0;
      while (edge_first[FE(f, (k + 2) % 3)] < 0) ++k;  // split edge from corner k to k+1
      const Index apex = F(f, (k + 2) % 3);
      loop.assign(1, F(f, k));
      for (int j = 1; j < rate; ++j) loop.push_back(edge_point(f, k, j));
      loop.push_back(F(f, (k + 1) % 3));
      for (std::size_t q = 0; q + 1 < loop.size(); ++q) out.F.row(row++) << apex, loop[q], loop[q + 1];
      continue;
    }
    // Two or three split edges: a fan from each corner would make flat
    // triangles along a split edge; a centroid vertex sees the whole polygon.
    place(centroid, f, 1.0 / 3, 1.0 / 3, 1.0 / 3);
    loop.clear();
    for (int k = 0; k < 3; ++k) {
      loop.push_back(F(f, k));
      if (edge_first[FE(f, (k + 2) % 3)] >= 0)
        for (int j = 1; j < rate; ++j) loop.push_back(edge_point(f, k, j));
    }
    for (std::size_t q = 0; q < loop.size(); ++q)
      out.F.row(row++) << centroid, loop[q], loop[(q + 1) % loop.size()];
    ++centroid;
  }
  assert(row == num_faces);
  out.new_faces = VectorXi::LinSpaced(num_faces - first_new, first_new, num_faces - 1);
  if (num_faces == first_new) out.new_faces.resize(0);

  // Region interior: vertices of refined faces off the region's rim.
  if (refine) {
    for (Index f = 0; f < nf; ++f)
      if (in_region[f])
        for (int k = 0; k < 3; ++k) out.region_interior(F(f, k)) = 1;
    for (Index i = interior_first; i < centroid_first; ++i) out.region_interior(i) = 1;
    for (Index e = 0; e < ne; ++e) {
      if (edge_first[e] < 0) continue;
      for (int j = 0; j < rate - 1; ++j) out.region_interior(edge_first[e] + j) = !rim_edge[e];
      if (rim_edge[e]) out.region_interior(E(e, 0)) = out.region_interior(E(e, 1)) = 0;
    }
  }
  if (progress) progress->report(0.4, "limit surface");

  evaluate_limit(V, F, out);
  if (progress) progress->report(1.0, "refine region");
  return out;
}

}  // namespace paramorph::paste
