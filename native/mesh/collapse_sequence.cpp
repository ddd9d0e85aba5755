#include "mesh/collapse_sequence.h"

#include <algorithm>
#include <cstdint>
#include <queue>

#include <Eigen/Geometry>

#include "common/errors.h"

namespace paramorph {

namespace {

using Vec3 = Eigen::Vector3d;
/// The plane quadric of Garland & Heckbert, upper triangle of the 4x4
/// matrix [A b; b^T c] packed as A00 A01 A02 b0 A11 A12 b1 A22 b2 c.
using Quadric = std::array<double, 10>;

Quadric plane_quadric(const Vec3& n, double d, double weight) {
  return {weight * n[0] * n[0], weight * n[0] * n[1], weight * n[0] * n[2], weight * n[0] * d,
          weight * n[1] * n[1], weight * n[1] * n[2], weight * n[1] * d,   weight * n[2] * n[2],
          weight * n[2] * d,    weight * d * d};
}

double evaluate(const Quadric& q, const Vec3& p) {
  const double x = p[0], y = p[1], z = p[2];
  return q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z +
         2 * q[6] * y + q[7] * z * z + 2 * q[8] * z + q[9];
}

struct Candidate {
  double cost;
  Index removed, kept;
  std::uint32_t stamp, kept_stamp;  ///< both ends' versions when this was costed
  bool operator<(const Candidate& other) const { return cost > other.cost; }  // min-heap
};

class Collapser {
 public:
  Collapser(const TriMesh& mesh, CollapseSequence& out) : V_(mesh.V()), G_(mesh.F()), out_(out) {
    const Index n = mesh.num_vertices(), m = mesh.num_faces();
    incident_.resize(std::size_t(n));
    quadric_.assign(std::size_t(n), Quadric{});
    area_.assign(std::size_t(n), 0.0);
    version_.assign(std::size_t(n), 0);
    vertex_alive_.assign(std::size_t(n), 1);
    face_alive_.assign(std::size_t(m), 1);
    for (Index f = 0; f < m; ++f) {
      const Vec3 a = V_.row(G_(f, 0)), b = V_.row(G_(f, 1)), c = V_.row(G_(f, 2));
      Vec3 normal = (b - a).cross(c - a);
      const double doubled = normal.norm();
      if (doubled > 0) normal /= doubled;
      const Quadric q = plane_quadric(normal, -normal.dot(a), 0.5 * doubled);
      for (int k = 0; k < 3; ++k) {
        const Index v = G_(f, k);
        incident_[std::size_t(v)].push_back(f);
        for (int i = 0; i < 10; ++i) quadric_[std::size_t(v)][std::size_t(i)] += q[std::size_t(i)];
        area_[std::size_t(v)] += 0.5 * doubled;
      }
    }
    alive_vertices_ = n;
  }

  void run(ProgressWindow& progress) {
    const Index total = alive_vertices_ - 4;
    for (int pass = 0; pass < 2 && alive_vertices_ > 4; ++pass) {
      geometric_ = pass == 0;
      // The last pass starts over from every edge: a collapse refused for its
      // link or its normals may be allowed now that its neighbours changed.
      queue_ = {};
      for (Index f = 0; f < Index(G_.rows()); ++f)
        if (face_alive_[std::size_t(f)])
          for (int k = 0; k < 3; ++k)
            if (G_(f, k) < G_(f, (k + 1) % 3)) push_edge(G_(f, k), G_(f, (k + 1) % 3));  // each edge once
      while (alive_vertices_ > 4 && !queue_.empty()) {
        const Candidate top = queue_.top();
        queue_.pop();
        if (version_[std::size_t(top.removed)] != top.stamp || version_[std::size_t(top.kept)] != top.kept_stamp)
          continue;  // an end was removed or absorbed another: costed again since
        if (!collapse(top.removed, top.kept)) continue;
        if (!geometric_) ++out_.geometric_refusals;
        const Index done = Index(out_.removed.size());
        if (done % 1024 == 0) progress.report(double(done) / double(std::max<Index>(total, 1)), "collapse");
      }
    }
    PM_REQUIRE(alive_vertices_ == 4, ComputeError, "collapse_sequence: stuck at ", alive_vertices_,
               " vertices with no edge that may collapse (is the mesh a closed genus-0 manifold?)");
    int k = 0;
    for (Index v = 0; v < Index(vertex_alive_.size()); ++v)
      if (vertex_alive_[std::size_t(v)]) out_.base_vertices[std::size_t(k++)] = v;
    k = 0;
    for (Index f = 0; f < Index(face_alive_.size()); ++f)
      if (face_alive_[std::size_t(f)]) out_.base_faces[std::size_t(k++)] = f;
    PM_REQUIRE(k == 4, ComputeError, "collapse_sequence: ", k, " faces left instead of a tetrahedron's 4");
  }

 private:
  /// Both terms are squared lengths: the edge's, and the removed vertex's
  /// mean squared distance from the planes it stood for, at the kept vertex
  /// (a limb's tip or a crease resists; a flat part goes by length).
  double cost(Index removed, Index kept) const {
    const Vec3 at = V_.row(kept);
    const double length2 = (at - Vec3(V_.row(removed))).squaredNorm();
    const double area = area_[std::size_t(removed)];
    return length2 + (area > 0 ? std::max(0.0, evaluate(quadric_[std::size_t(removed)], at)) / area : 0.0);
  }

  /// The cheaper way round of edge (a, b) (the queue is most of the time:
  /// one entry per edge, not two).
  void push_edge(Index a, Index b) {
    const double ab = cost(a, b), ba = cost(b, a);
    if (ab <= ba)
      queue_.push({ab, a, b, version_[std::size_t(a)], version_[std::size_t(b)]});
    else
      queue_.push({ba, b, a, version_[std::size_t(b)], version_[std::size_t(a)]});
  }

  /// The removed vertex's neighbours (sorted).
  void neighbours(Index v, std::vector<Index>& out) const {
    out.clear();
    for (const Index f : incident_[std::size_t(v)])
      for (int k = 0; k < 3; ++k)
        if (G_(f, k) != v) out.push_back(G_(f, k));
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  bool collapse(Index v, Index u) {
    // The faces around v counter-clockwise, as (v, a, b) with a -> b.
    ring_next_.clear();
    for (const Index f : incident_[std::size_t(v)]) {
      int c = 0;
      while (G_(f, c) != v) ++c;
      ring_next_.push_back({G_(f, (c + 1) % 3), G_(f, (c + 2) % 3), f});
    }
    // Link condition: v and u share exactly the two vertices across the edge.
    neighbours(v, nv_);
    neighbours(u, nu_);
    if (!std::binary_search(nv_.begin(), nv_.end(), u)) return false;
    std::size_t shared = 0;
    for (std::size_t i = 0, j = 0; i < nv_.size() && j < nu_.size();) {
      if (nv_[i] < nu_[j]) ++i;
      else if (nu_[j] < nv_[i]) ++j;
      else ++shared, ++i, ++j;
    }
    if (shared != 2 || nu_.size() + nv_.size() - 4 < 3) return false;
    // The ring from u round to u.
    ring_.assign(1, u);
    face_order_.clear();
    for (std::size_t step = 0; step < ring_next_.size(); ++step) {
      const auto it = std::find_if(ring_next_.begin(), ring_next_.end(),
                                   [&](const Step& s) { return s.from == ring_.back(); });
      if (it == ring_next_.end()) return false;  // not one fan: never for a validated mesh
      face_order_.push_back(it->face);
      ring_.push_back(it->to);
    }
    if (ring_.back() != u) return false;
    ring_.pop_back();
    // The two across-edge faces' third vertices must keep three neighbours.
    for (const Index side : {ring_[1], ring_.back()}) {
      neighbours(side, nside_);
      if (nside_.size() <= 3) return false;
    }
    if (geometric_) {
      const Vec3 from = V_.row(v), to = V_.row(u);
      for (std::size_t k = 1; k + 1 < face_order_.size(); ++k) {
        const Vec3 a = V_.row(ring_[k]), b = V_.row(ring_[k + 1]);
        if ((a - from).cross(b - from).dot((a - to).cross(b - to)) <= 0) return false;  // turns over in 3D
      }
    }

    // Record, then apply.
    out_.removed.push_back(v);
    out_.kept.push_back(u);
    out_.faces.items.insert(out_.faces.items.end(), face_order_.begin(), face_order_.end());
    out_.faces.offsets.push_back(Index(out_.faces.items.size()));
    out_.rings.items.insert(out_.rings.items.end(), ring_.begin(), ring_.end());
    out_.rings.offsets.push_back(Index(out_.rings.items.size()));
    const Index first = face_order_.front(), last = face_order_.back();
    for (const Index f : {first, last}) {
      face_alive_[std::size_t(f)] = 0;
      for (int k = 0; k < 3; ++k) {
        const Index w = G_(f, k);
        if (w == v) continue;
        auto& list = incident_[std::size_t(w)];
        list.erase(std::find(list.begin(), list.end(), f));
      }
    }
    auto& into = incident_[std::size_t(u)];
    for (std::size_t k = 1; k + 1 < face_order_.size(); ++k) {
      const Index f = face_order_[k];
      for (int c = 0; c < 3; ++c)
        if (G_(f, c) == v) G_(f, c) = u;
      into.push_back(f);
    }
    incident_[std::size_t(v)].clear();
    vertex_alive_[std::size_t(v)] = 0;
    ++version_[std::size_t(v)];
    --alive_vertices_;
    for (int i = 0; i < 10; ++i) quadric_[std::size_t(u)][std::size_t(i)] += quadric_[std::size_t(v)][std::size_t(i)];
    area_[std::size_t(u)] += area_[std::size_t(v)];
    ++version_[std::size_t(u)];
    neighbours(u, nu_);
    for (const Index w : nu_) push_edge(u, w);
    return true;
  }

  struct Step {
    Index from, to, face;
  };

  const MatrixX3d& V_;
  MatrixX3i G_;
  CollapseSequence& out_;
  std::vector<std::vector<Index>> incident_;
  std::vector<Quadric> quadric_;
  std::vector<double> area_;
  std::vector<std::uint32_t> version_;
  std::vector<char> vertex_alive_, face_alive_;
  Index alive_vertices_ = 0;
  bool geometric_ = true;
  std::priority_queue<Candidate> queue_;
  std::vector<Step> ring_next_;
  std::vector<Index> ring_, face_order_, nv_, nu_, nside_;
};

}  // namespace

CollapseSequence collapse_sequence(const TriMesh& mesh, ProgressWindow progress) {
  PM_REQUIRE(mesh.num_vertices() >= 4 && mesh.num_faces() >= 4, InvalidInputError,
             "collapse_sequence: a closed mesh has at least 4 vertices and 4 faces");
  CollapseSequence out;
  out.faces.offsets.assign(1, 0);
  out.rings.offsets.assign(1, 0);
  out.removed.reserve(std::size_t(mesh.num_vertices()));
  out.kept.reserve(std::size_t(mesh.num_vertices()));
  Collapser(mesh, out).run(progress);
  progress.report(1.0, "collapse");
  return out;
}

void apply_collapse(const CollapseSequence& s, Index c, MatrixX3i& F, std::vector<char>& alive) {
  const Index begin = s.faces.begin(c), end = s.faces.end(c);
  alive[std::size_t(s.faces.items[begin])] = 0;
  alive[std::size_t(s.faces.items[end - 1])] = 0;
  for (Index k = begin + 1; k + 1 < end; ++k)
    for (int corner = 0; corner < 3; ++corner)
      if (F(s.faces.items[k], corner) == s.removed[c]) F(s.faces.items[k], corner) = s.kept[c];
}

void undo_collapse(const CollapseSequence& s, Index c, MatrixX3i& F, std::vector<char>& alive) {
  const Index begin = s.faces.begin(c), end = s.faces.end(c);
  alive[std::size_t(s.faces.items[begin])] = 1;
  alive[std::size_t(s.faces.items[end - 1])] = 1;
  for (Index k = begin + 1; k + 1 < end; ++k)
    for (int corner = 0; corner < 3; ++corner)
      if (F(s.faces.items[k], corner) == s.kept[c]) F(s.faces.items[k], corner) = s.removed[c];
}

}  // namespace paramorph
