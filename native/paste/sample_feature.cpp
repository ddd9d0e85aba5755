#include "paste/sample_feature.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "paste/locate_in_map.h"
#include "paste/map_frames.h"

namespace paramorph::paste {

BaseSample sample_base(const Feature& feature, const MatrixX2d& uv) {
  PM_REQUIRE(uv.allFinite(), InvalidInputError, "uv must be finite");
  const Index nq = Index(uv.rows());
  const MapLocation at = MapLocator(feature.base_uv, feature.F).locate(uv);
  const MapFrames frames = map_frames(feature.base_V, feature.F, feature.base_uv);
  BaseSample s{interpolate(feature.F, at, feature.base_V), MatrixX3d(nq, 3), MatrixX3d(nq, 3),
               MatrixX3d(nq, 3), at.distance};
  for (Index q = 0; q < nq; ++q) {
    const Eigen::Matrix3d R = frame_at(frames, feature.F, at.face[q], at.bary.row(q).transpose());
    s.e_u.row(q) = R.col(0).transpose();
    s.e_v.row(q) = R.col(1).transpose();
    s.n.row(q) = R.col(2).transpose();
  }
  return s;
}

MatrixX3d bilinear_displacement(const Feature& feature, const MatrixX2d& uv) {
  const int r = feature.resolution;
  PM_REQUIRE(r >= 2 && feature.displacement.rows() == Index(r) * r && feature.grid_spacing > 0,
             InvalidInputError, "the feature has no displacement grid");
  MatrixX3d out(uv.rows(), 3);
  auto cell = [&](double x, int& k) {  // grid coordinate -> cell index and weight in it
    x = std::clamp(x, 0.0, double(r - 1));
    k = std::min(int(std::floor(x)), r - 2);
    return x - k;
  };
  for (Index q = 0; q < Index(uv.rows()); ++q) {
    int j, i;
    const double s = cell((uv(q, 0) - feature.grid_origin.x()) / feature.grid_spacing, j);
    const double t = cell((uv(q, 1) - feature.grid_origin.y()) / feature.grid_spacing, i);
    const auto node = [&](int a, int b) { return feature.displacement.row(Index(a) * r + b); };
    out.row(q) = (1 - t) * ((1 - s) * node(i, j) + s * node(i, j + 1)) +
                 t * ((1 - s) * node(i + 1, j) + s * node(i + 1, j + 1));
  }
  return out;
}

FeatureSample sample_feature(const Feature& feature, const MatrixX2d& uv) {
  BaseSample b = sample_base(feature, uv);
  FeatureSample s;
  s.displacement = bilinear_displacement(feature, uv);
  s.position = b.base + (b.e_u.array().colwise() * s.displacement.col(0).array() +
                         b.e_v.array().colwise() * s.displacement.col(1).array() +
                         b.n.array().colwise() * s.displacement.col(2).array())
                            .matrix();
  s.base = std::move(b.base);
  s.e_u = std::move(b.e_u);
  s.e_v = std::move(b.e_v);
  s.n = std::move(b.n);
  s.distance = std::move(b.distance);
  return s;
}

}  // namespace paramorph::paste
