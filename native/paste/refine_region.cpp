// Uniform Loop refinement of a mesh region with limit positions and normals
// (paste/refine_region.h; thesis 5.2, DESIGN.md §4.5 step 3).
#include "paste/refine_region.h"

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <unordered_map>

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
void require_manifold_mesh(const TriMesh& mesh) {
  const MeshReport report = validate(mesh);
  require_manifold(report);
  PM_REQUIRE(report.degenerate_faces.empty(), DegenerateFaceError,
             "degenerate faces (repeated indices or zero area): ", format_indices(report.degenerate_faces));
}

/// A point as OpenSubdiv's primvar refiner reads and writes it.
struct LimitPoint {
  double x[3];
  void Clear() { x[0] = x[1] = x[2] = 0.0; }
  void AddWithWeight(const LimitPoint& p, double w) {
    x[0] += w * p.x[0];
    x[1] += w * p.x[1];
    x[2] += w * p.x[2];
  }
};

/// Loop limit positions and unit normals of the mesh's own vertices, from
/// their limit masks (OpenSubdiv's PrimvarRefiner::Limit): linear in the
/// mesh. Bfr's patch of a face at a vertex of valence n costs O(n^2) to set
/// up, so evaluating every vertex of a fan around one such vertex through
/// its faces grew with n^3 (2000 -> 22 s, 4000 -> 176 s; issue 19).
void vertex_limits(const Far::TopologyRefiner& refiner, const MatrixX3d& V, MatrixX3d& P, MatrixX3d& N) {
  const Index n = Index(V.rows());
  const std::size_t count = static_cast<std::size_t>(n);
  std::vector<LimitPoint> src(count), pos(count), du(count), dv(count);
  for (Index v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) src[std::size_t(v)].x[k] = V(v, k);
  Far::PrimvarRefinerReal<double>(refiner).Limit(src, pos, du, dv);
  P.resize(n, 3);
  N.resize(n, 3);
  for (Index v = 0; v < n; ++v) {
    P.row(v) << pos[std::size_t(v)].x[0], pos[std::size_t(v)].x[1], pos[std::size_t(v)].x[2];
    const Eigen::Vector3d a(du[std::size_t(v)].x), b(dv[std::size_t(v)].x);
    N.row(v) = a.cross(b).transpose();
  }
}

/// Loop limit position and normal at (face, bary) for the points listed in
/// `which` (indices into faces/bary); P and N are written at those rows only.
/// Points at a corner of their face take the vertex's limit (vertex_P,
/// vertex_N: vertex_limits()); the others are evaluated face by face (Bfr).
void evaluate_limit(const Far::TopologyRefiner& refiner, const MatrixX3d& V0, const MatrixX3i& F0,
                    const MatrixX3d& vertex_P, const MatrixX3d& vertex_N, const VectorXi& faces,
                    const MatrixX3d& bary, const std::vector<Index>& which, MatrixX3d& P, MatrixX3d* N,
                    Progress* progress = nullptr, double progress_from = 0.0, double progress_to = 1.0) {
  const Index nf = Index(F0.rows());
  if (which.empty() || nf == 0) return;
  std::vector<Index> inside;  // points not at a corner
  inside.reserve(which.size());
  for (const Index i : which) {
    Index corner = -1;
    for (int k = 0; k < 3; ++k)
      if (bary(i, k) >= 1.0 - 1e-12) corner = k;
    if (corner < 0) {
      inside.push_back(i);
      continue;
    }
    const Index f = faces(i), v = F0(f, corner);
    P.row(i) = vertex_P.row(v);
    if (!N) continue;
    // The masks' tangents span the tangent plane; orient the normal like the face.
    const Eigen::RowVector3d a = V0.row(F0(f, 0)), b = V0.row(F0(f, 1)), c = V0.row(F0(f, 2));
    const Eigen::RowVector3d flat_normal = (b - a).cross(c - a).normalized();
    Eigen::RowVector3d normal = vertex_N.row(v);
    if (normal.dot(flat_normal) < 0) normal = -normal;
    N->row(i) = normal.norm() > 1e-300 ? normal.normalized() : flat_normal;
  }
  // Points grouped by face (sort), so each Surface is built once.
  std::vector<Index>& order = inside;
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return faces(a) < faces(b); });
  std::vector<std::size_t> starts;
  for (std::size_t k = 0; k < order.size(); ++k)
    if (k == 0 || faces(order[k]) != faces(order[k - 1])) starts.push_back(k);
  starts.push_back(order.size());

  const Bfr::Surface<double>::PointDescriptor point(3);
  const std::int64_t groups = std::int64_t(starts.size()) - 1;
  // In chunks, so progress (and cancel) lands between them.
  constexpr std::int64_t kChunk = 256;
  for (std::int64_t chunk = 0; chunk < groups; chunk += kChunk) {
    if (progress)
      progress->report(progress_from + (progress_to - progress_from) * double(chunk) / double(groups),
                       "limit surface");
    const std::int64_t chunk_end = std::min(groups, chunk + kChunk);
#pragma omp parallel if (chunk_end - chunk > 64)
    {
      const Bfr::RefinerSurfaceFactory<> factory(refiner);
      Bfr::Surface<double> surface;
      std::vector<double> patch;
#pragma omp for schedule(dynamic, 64)
      for (std::int64_t g = chunk; g < chunk_end; ++g) {
        const Index f = faces(order[starts[std::size_t(g)]]);
        const bool ok = factory.InitVertexSurface(f, &surface);
        if (ok) {
          patch.resize(3 * std::size_t(surface.GetNumPatchPoints()));
          surface.PreparePatchPoints(V0.data(), point, patch.data(), point);
        }
        const Eigen::RowVector3d a = V0.row(F0(f, 0)), b = V0.row(F0(f, 1)), c = V0.row(F0(f, 2));
        const Eigen::RowVector3d flat_normal = (b - a).cross(c - a).normalized();
        for (std::size_t k = starts[std::size_t(g)]; k < starts[std::size_t(g) + 1]; ++k) {
          const Index i = order[k];
          if (!ok) {  // no limit surface for this face: keep it flat
            P.row(i) = bary(i, 0) * a + bary(i, 1) * b + bary(i, 2) * c;
            if (N) N->row(i) = flat_normal;
            continue;
          }
          // Bfr's triangle parameterization: corner 0 at (0, 0), 1 at (1, 0), 2 at (0, 1).
          const double uv[2] = {bary(i, 1), bary(i, 2)};
          Eigen::RowVector3d X, du, dv;
          surface.Evaluate(uv, patch.data(), point, X.data(), du.data(), dv.data());
          P.row(i) = X;
          // Du x Dv vanishes only where the parameterization degenerates; the
          // flat normal is then the best local answer.
          const Eigen::RowVector3d normal = du.cross(dv);
          if (N) N->row(i) = normal.norm() > 1e-300 ? normal.normalized() : flat_normal;
        }
      }
    }
  }
}

}  // namespace

struct RegionRefiner::Impl {
  TriMesh mesh;
  std::unique_ptr<Far::TopologyRefiner> refiner;  ///< null for a mesh without faces
  MatrixX3d vertex_limit, vertex_normal;          ///< vertex_limits() of the mesh
  explicit Impl(TriMesh m) : mesh(std::move(m)) {}
};

RegionRefiner::RegionRefiner(const MatrixX3d& V, const MatrixX3i& F) {
  validate_arrays(V, F);
  impl_ = std::make_unique<Impl>(TriMesh(V, F));
  require_manifold_mesh(impl_->mesh);
  if (F.rows() == 0) return;
  Far::TopologyDescriptor desc;
  const std::vector<int> valences(std::size_t(F.rows()), 3);
  desc.numVertices = int(V.rows());
  desc.numFaces = int(F.rows());
  desc.numVertsPerFace = valences.data();
  desc.vertIndicesPerFace = impl_->mesh.F().data();
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  impl_->refiner.reset(Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, sdc)));
  PM_REQUIRE(impl_->refiner, NonManifoldError, "OpenSubdiv could not build the mesh's topology");
  vertex_limits(*impl_->refiner, V, impl_->vertex_limit, impl_->vertex_normal);
}

RegionRefiner::~RegionRefiner() = default;
RegionRefiner::RegionRefiner(RegionRefiner&&) noexcept = default;
RegionRefiner& RegionRefiner::operator=(RegionRefiner&&) noexcept = default;

const TriMesh& RegionRefiner::mesh() const { return impl_->mesh; }

MatrixX3d RegionRefiner::limit(const VectorXi& faces, const MatrixX3d& bary, MatrixX3d* normals) const {
  const MatrixX3d& V = impl_->mesh.V();
  const MatrixX3i& F = impl_->mesh.F();
  PM_REQUIRE(bary.rows() == faces.size(), InvalidInputError, "faces and bary differ in length");
  for (Index q = 0; q < Index(faces.size()); ++q)
    PM_REQUIRE(faces(q) >= 0 && faces(q) < Index(F.rows()), InvalidInputError, "face ", faces(q),
               " is out of range [0, ", F.rows(), ")");
  MatrixX3d P(faces.size(), 3);
  if (normals) normals->setZero(faces.size(), 3);
  std::vector<Index> all(std::size_t(faces.size()));
  for (Index q = 0; q < Index(all.size()); ++q) all[std::size_t(q)] = q;
  evaluate_limit(*impl_->refiner, V, F, impl_->vertex_limit, impl_->vertex_normal, faces, bary, all, P, normals);
  return P;
}

RefinedRegion RegionRefiner::refine(const std::vector<Index>& region_faces, int level, LimitAt limit_at,
                                    Progress* progress) const {
  const TriMesh& mesh = impl_->mesh;
  const MatrixX3d& V = mesh.V();
  const MatrixX3i& F = mesh.F();
  PM_REQUIRE(level >= 0 && level <= 8, InvalidInputError, "level must be in 0..8, got ", level);
  const Index nv = Index(V.rows()), nf = Index(F.rows());
  std::vector<char> in_region(std::size_t(nf), 0);
  std::vector<Index> region;  // ascending, no duplicates
  region.reserve(region_faces.size());
  for (const Index f : region_faces) {
    PM_REQUIRE(f >= 0 && f < nf, InvalidInputError, "region face ", f, " is out of range [0, ", nf,
               ")");
    if (!in_region[f]) region.push_back(f);
    in_region[f] = 1;
  }
  std::sort(region.begin(), region.end());
  if (progress) progress->report(0.0, "refine region");
  const MatrixX2i& E = mesh.edges();
  const MatrixX3i& FE = mesh.face_edges();
  const Csr& EF = mesh.edge_faces();

  RefinedRegion out;
  const int rate = 1 << level;
  const bool refine = level > 0 && !region.empty();
  if (!refine) {  // nothing is refined: every face stays
    region.clear();
    std::fill(in_region.begin(), in_region.end(), 0);
  }

  // Edges of region faces get rate - 1 points each, ordered from E(e, 0) to
  // E(e, 1); both faces of the edge use these (no cracks, no T-junctions).
  // Only the region's edges are visited: the cost follows the region.
  std::vector<Index> split_edges;
  for (const Index f : region)
    for (int k = 0; k < 3; ++k) split_edges.push_back(FE(f, k));
  std::sort(split_edges.begin(), split_edges.end());
  split_edges.erase(std::unique(split_edges.begin(), split_edges.end()), split_edges.end());
  std::unordered_map<Index, Index> edge_first;  // split edge -> its first new vertex
  edge_first.reserve(split_edges.size() * 2);
  std::vector<Index> edge_owner(split_edges.size(), -1);  // a region face holding the edge
  std::vector<char> rim_edge(split_edges.size(), 0);
  Index next = nv;
  for (std::size_t s = 0; s < split_edges.size(); ++s) {
    const Index e = split_edges[s];
    Index region_count = 0;
    for (Index k = EF.begin(e); k < EF.end(e); ++k)
      if (in_region[EF.items[k]]) {
        if (edge_owner[s] < 0) edge_owner[s] = EF.items[k];
        ++region_count;
      }
    edge_first[e] = next;
    next += rate - 1;
    rim_edge[s] = region_count < 2;  // to a face outside, or the mesh's boundary
  }
  const auto first_point = [&](Index e) -> Index {
    const auto it = edge_first.find(e);
    return it == edge_first.end() ? -1 : it->second;
  };

  // Faces outside the region with a split edge are re-triangulated.
  std::vector<char> neighbour(std::size_t(nf), 0);
  std::vector<Index> neighbours;
  for (const Index e : split_edges)
    for (Index k = EF.begin(e); k < EF.end(e); ++k) {
      const Index f = EF.items[k];
      if (in_region[f]) continue;
      if (neighbour[f] == 0) neighbours.push_back(f);
      ++neighbour[f];
    }
  std::sort(neighbours.begin(), neighbours.end());
  Index num_centroids = 0;
  for (const Index f : neighbours) num_centroids += neighbour[f] >= 2;

  const Pattern pattern = tessellation_pattern(rate);
  const Index per_face_interior = Index(pattern.interior.size());
  const Index num_region = Index(region.size());
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
  for (std::size_t s = 0; s < split_edges.size(); ++s) {
    const Index e = split_edges[s], f = edge_owner[s];
    const int ka = corner_of(f, E(e, 0)), kb = corner_of(f, E(e, 1));
    for (int j = 1; j < rate; ++j) {
      const double t = double(j) / rate;
      double b[3] = {0.0, 0.0, 0.0};
      b[ka] = 1.0 - t;
      b[kb] = t;
      const Index i = edge_first[e] + j - 1;
      place(i, f, b[0], b[1], b[2]);
      out.V.row(i) = (1.0 - t) * V.row(E(e, 0)) + t * V.row(E(e, 1));  // exact on the edge
    }
  }
  if (progress) progress->report(0.2, "refine region");

  // Output faces: untouched first, then region tessellations, then neighbours.
  Index neighbour_faces = 0;
  for (const Index f : neighbours)
    neighbour_faces += neighbour[f] == 1 ? rate : 3 + neighbour[f] * (rate - 1);
  const Index num_untouched = nf - num_region - Index(neighbours.size());
  const Index num_faces = num_untouched + num_region * Index(pattern.facets.size()) + neighbour_faces;
  out.F.resize(num_faces, 3);
  out.replaced_faces.resize(num_region + Index(neighbours.size()));
  Index row = 0, replaced = 0;
  for (Index f = 0; f < nf; ++f) {
    if (in_region[f] || neighbour[f]) out.replaced_faces(replaced++) = f;
    else out.F.row(row++) = F.row(f);
  }
  const Index first_new = row;
  out.new_face_parents.resize(num_faces - first_new);
  const auto emitted_by = [&](Index f, Index from) {  // rows [from, row) came from face f
    for (Index k = from; k < row; ++k) out.new_face_parents(k - first_new) = f;
  };

  // The global vertex of point j of the edge from corner k to corner k+1 of f.
  const auto edge_point = [&](Index f, int k, int j) -> Index {
    const Index e = FE(f, (k + 2) % 3);
    return F(f, k) == E(e, 0) ? edge_first[e] + j - 1 : edge_first[e] + rate - 1 - j;
  };

  std::vector<Index> boundary_map(pattern.boundary.size());
  Index region_index = 0;
  for (const Index f : region) {
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
    const Index from = row;
    for (const auto& facet : pattern.facets) {
      for (int c = 0; c < 3; ++c)
        out.F(row, c) = facet[c] < nb ? boundary_map[facet[c]] : first_interior + facet[c] - nb;
      ++row;
    }
    emitted_by(f, from);
  }

  Index centroid = centroid_first;
  std::vector<Index> loop;
  for (const Index f : neighbours) {
    const Index from = row;
    if (neighbour[f] == 1) {
      // Fan from the corner opposite the one split edge: no extra vertex.
      int k = 0;
      while (first_point(FE(f, (k + 2) % 3)) < 0) ++k;  // split edge from corner k to k+1
      const Index apex = F(f, (k + 2) % 3);
      loop.assign(1, F(f, k));
      for (int j = 1; j < rate; ++j) loop.push_back(edge_point(f, k, j));
      loop.push_back(F(f, (k + 1) % 3));
      for (std::size_t q = 0; q + 1 < loop.size(); ++q) out.F.row(row++) << apex, loop[q], loop[q + 1];
      emitted_by(f, from);
      continue;
    }
    // Two or three split edges: a fan from each corner would make flat
    // triangles along a split edge; a centroid vertex sees the whole polygon.
    place(centroid, f, 1.0 / 3, 1.0 / 3, 1.0 / 3);
    loop.clear();
    for (int k = 0; k < 3; ++k) {
      loop.push_back(F(f, k));
      if (first_point(FE(f, (k + 2) % 3)) >= 0)
        for (int j = 1; j < rate; ++j) loop.push_back(edge_point(f, k, j));
    }
    for (std::size_t q = 0; q < loop.size(); ++q)
      out.F.row(row++) << centroid, loop[q], loop[(q + 1) % loop.size()];
    emitted_by(f, from);
    ++centroid;
  }
  assert(row == num_faces);
  out.new_faces = VectorXi::LinSpaced(num_faces - first_new, first_new, num_faces - 1);
  if (num_faces == first_new) out.new_faces.resize(0);

  // Region interior: vertices of refined faces off the region's rim.
  for (const Index f : region)
    for (int k = 0; k < 3; ++k) out.region_interior(F(f, k)) = 1;
  for (Index i = interior_first; i < centroid_first; ++i) out.region_interior(i) = 1;
  for (std::size_t s = 0; s < split_edges.size(); ++s) {
    const Index e = split_edges[s];
    for (int j = 0; j < rate - 1; ++j) out.region_interior(edge_first[e] + j) = !rim_edge[s];
    if (rim_edge[s]) out.region_interior(E(e, 0)) = out.region_interior(E(e, 1)) = 0;
  }
  if (progress) progress->report(0.4, "limit surface");

  out.limit = out.V;
  out.limit_normal = MatrixX3d::Zero(total, 3);
  std::vector<Index> which;
  if (limit_at == LimitAt::AllVertices) {
    for (Index i = 0; i < total; ++i)
      if (out.base_face(i) >= 0) which.push_back(i);
  } else if (limit_at == LimitAt::RegionVertices) {
    std::vector<char> corner(std::size_t(nv), 0);
    for (const Index f : region)
      for (int k = 0; k < 3; ++k) corner[std::size_t(F(f, k))] = 1;
    for (Index v = 0; v < nv; ++v)
      if (corner[std::size_t(v)] && out.base_face(v) >= 0) which.push_back(v);
    for (Index i = nv; i < total; ++i) which.push_back(i);
  }
  if (impl_->refiner)
    evaluate_limit(*impl_->refiner, V, F, impl_->vertex_limit, impl_->vertex_normal, out.base_face, out.bary,
                   which, out.limit, &out.limit_normal, progress, 0.4, 1.0);
  if (progress) progress->report(1.0, "refine region");
  return out;
}

RefinedRegion refine_region(const MatrixX3d& V, const MatrixX3i& F,
                            const std::vector<Index>& region_faces, int level,
                            Progress* progress) {
  return RegionRefiner(V, F).refine(region_faces, level, LimitAt::AllVertices, progress);
}

}  // namespace paramorph::paste
