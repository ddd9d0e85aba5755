#include "param/planar/untangle.h"

#include <Eigen/Dense>
#include <cmath>

#include "common/errors.h"

namespace paramorph::planar {

namespace {

double det2(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d e1 = b - a, e2 = c - a;
  return e1.x() * e2.y() - e1.y() * e2.x();
}

double total_abs_area(const MatrixX3i& F, const MatrixX2d& uv) {
  double s = 0.0;
  for (Index f = 0; f < Index(F.rows()); ++f)
    s += std::abs(det2(uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2))));
  return s;
}

}  // namespace

std::vector<Index> folded_faces(const MatrixX3i& F, const MatrixX2d& uv) {
  std::vector<Index> out;
  for (Index f = 0; f < Index(F.rows()); ++f)
    if (!(det2(uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2))) > 0.0)) out.push_back(f);
  return out;
}

UntangleResult untangle(const MatrixX3i& F, MatrixX2d& uv, const std::vector<char>& fixed,
                        const UntangleOptions& o, ProgressWindow progress) {
  PM_REQUIRE(Index(fixed.size()) == Index(uv.rows()), InvalidInputError,
             "untangle: one fixed flag per vertex expected");
  const Index m = Index(F.rows());
  UntangleResult result;
  double delta = 0.5;
  double area = total_abs_area(F, uv);
  // β from the mean |det|: a scale-free "small triangle" threshold.
  const double beta = o.relative_min_area * area / std::max<Index>(m, 1);
  MatrixX2d step(uv.rows(), 2), trial;
  while (result.iterations < o.max_iterations && delta >= o.min_delta) {
    step.setZero();
    bool any = false;
    for (Index f = 0; f < m; ++f) {
      const Eigen::Vector2d p[3] = {uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2))};
      const double det = det2(p[0], p[1], p[2]);
      if (det > beta) continue;
      any = any || det <= 0.0;
      const double shear_factor = det >= -beta ? 1.0 - std::abs(det) / beta : 0.0;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d& v = p[k];
        const Eigen::Vector2d& a = p[(k + 1) % 3];
        const Eigen::Vector2d& b = p[(k + 2) % 3];
        const Eigen::Vector2d e = b - a;
        // d det / d v: the opposite edge rotated by 90° (2.23–2.25).
        Eigen::Vector2d move(-e.y(), e.x());
        // Shear (Fig. 2.10): when an angle at a or b is obtuse, slide v along
        // the opposite edge back over it, towards the edge's midpoint.
        if (shear_factor > 0.0 && ((v - a).dot(e) < 0.0 || (v - b).dot(-e) < 0.0)) {
          const double len2 = e.squaredNorm();
          if (len2 > 0.0) move += shear_factor * ((0.5 * (a + b) - v).dot(e) / len2) * e;
        }
        step.row(F(f, k)) += move.transpose();
      }
    }
    if (!any) break;  // nothing inverted or degenerate left
    for (Index v = 0; v < Index(uv.rows()); ++v)
      if (fixed[v]) step.row(v).setZero();
    trial = uv + delta * step;
    const double trial_area = total_abs_area(F, trial);
    ++result.iterations;
    if (trial_area < area) {
      uv.swap(trial);
      area = trial_area;
    } else {
      delta *= 0.5;  // Algorithm 2, line 8: the total |area| stopped improving
    }
    if (result.iterations % 64 == 0)
      progress.report(double(result.iterations) / o.max_iterations, "untangle");
  }
  result.folded = Index(folded_faces(F, uv).size());
  return result;
}

}  // namespace paramorph::planar
