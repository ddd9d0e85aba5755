// Small closed meshes built in the C++ tests.
#pragma once

#include <array>
#include <cmath>
#include <vector>
#include <map>
#include <utility>

#include "mesh/types.h"

namespace paramorph::test_meshes {

/// Icosahedron subdivided `levels` times, vertices on the unit sphere,
/// faces counter-clockwise seen from outside.
inline std::pair<MatrixX3d, MatrixX3i> icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return midpoint[key] = int(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& tri : f) {
      const int a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  MatrixX3d V(v.size(), 3);
  MatrixX3i F(f.size(), 3);
  for (std::size_t i = 0; i < v.size(); ++i) V.row(i) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i) F.row(i) = f[i].transpose().cast<Index>();
  return {V, F};
}

/// The icosphere pushed into a lumpy, non-convex blob (deterministic).
inline std::pair<MatrixX3d, MatrixX3i> lumpy_blob(int levels) {
  auto [V, F] = icosphere(levels);
  for (Index i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i).transpose();
    const double r = 1.0 + 0.35 * std::sin(3.0 * p.x()) * std::cos(2.0 * p.y()) + 0.5 * p.z() * p.z();
    V.row(i) = (r * p.cwiseProduct(Eigen::Vector3d(1.0, 1.6, 0.8))).transpose();
  }
  return {V, F};
}

/// Closed box [-h, h] (h = half_extents) with every side an n by n grid of
/// cells split into two triangles, welded along the edges; counter-clockwise
/// seen from outside. Its convex hull is the box itself.
inline std::pair<MatrixX3d, MatrixX3i> box_grid(int n, const Eigen::Vector3d& half_extents) {
  std::map<std::array<int, 3>, Index> id;  // integer lattice point -> vertex
  std::vector<Eigen::Vector3i> faces;
  auto vertex = [&](std::array<int, 3> p) {
    auto it = id.find(p);
    if (it != id.end()) return it->second;
    const Index next = Index(id.size());
    return id[p] = next;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
    for (int side = 0; side <= 1; ++side)
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          auto at = [&](int du, int dv) {
            std::array<int, 3> p{};
            p[a] = side * n, p[b] = u + du, p[c] = v + dv;
            return vertex(p);
          };
          const Index p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          if (side == 1) {
            faces.push_back({p00, p10, p11});
            faces.push_back({p00, p11, p01});
          } else {
            faces.push_back({p00, p11, p10});
            faces.push_back({p00, p01, p11});
          }
        }
  }
  MatrixX3d V(id.size(), 3);
  for (const auto& [p, i] : id)
    for (int k = 0; k < 3; ++k) V(i, k) = half_extents[k] * (2.0 * p[k] / n - 1.0);
  MatrixX3i F(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose();
  return {V, F};
}

/// Faces of an (n+1)² vertex grid, vertex (i, j) at row i (n + 1) + j, two
/// triangles per cell, counter-clockwise when i runs along +x and j along +y.
inline MatrixX3i grid_faces(int n) {
  MatrixX3i F(2 * n * n, 3);
  Index k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Index a = i * (n + 1) + j, b = a + n + 1;
      F.row(k++) << a, b, b + 1;
      F.row(k++) << a, b + 1, a + 1;
    }
  return F;
}

/// An open (n+1)² grid patch over the unit square lifted into a bumpy height
/// field, faces counter-clockwise seen from +z.
inline std::pair<MatrixX3d, MatrixX3i> bumpy_grid(int n) {
  MatrixX3d V((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(i) / n, y = double(j) / n;
      V.row(i * (n + 1) + j) << x, y, 0.3 * std::sin(4 * x) * std::sin(3 * y);
    }
  return {V, grid_faces(n)};
}

/// A plane grid over [-1, 1]² ((n+1)² vertices, faces counter-clockwise seen
/// from +z) lifted by a Gaussian bump z = h exp(-r²/s²) where r < R, and the
/// faces whose centroid lies within r < R (the feature).
struct BumpGrid {
  MatrixX3d V;
  MatrixX3i F;
  std::vector<Index> feature;
};
inline BumpGrid gaussian_bump_grid(int n, double h, double s, double R) {
  BumpGrid g{MatrixX3d((n + 1) * (n + 1), 3), grid_faces(n), {}};
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = -1 + 2.0 * i / n, y = -1 + 2.0 * j / n, r = std::hypot(x, y);
      g.V.row(i * (n + 1) + j) << x, y, r < R ? h * std::exp(-r * r / (s * s)) : 0.0;
    }
  for (Index f = 0; f < Index(g.F.rows()); ++f) {
    const Eigen::RowVector3d c = (g.V.row(g.F(f, 0)) + g.V.row(g.F(f, 1)) + g.V.row(g.F(f, 2))) / 3.0;
    if (std::hypot(c.x(), c.y()) < R) g.feature.push_back(f);
  }
  return g;
}

}  // namespace paramorph::test_meshes
