#include "morph/registered_pairs.h"

#include "morph/pair_nearest_points.h"

namespace paramorph::morph {

Registration register_matched(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                              const MatrixX3i& FB, const features::FeatureMatch& match,
                              const RegisterOptions& options, Progress* progress) {
  const Eigen::RowVector3d cb = match.centre_b.transpose(), ca = match.centre_a.transpose();
  const std::vector<PolynomialWarp> starts = {
      PolynomialWarp::similarity(cb, match.scale_b, Eigen::Matrix3d::Identity(), ca, match.scale_a),
      PolynomialWarp::similarity(cb, match.scale_b, match.rotation, ca, match.scale_a)};
  return register_surfaces(VA, FA, VB, FB, starts, options, progress);
}

RegisteredPairs registered_pairs(const MatrixX3d& VA, const MatrixX3d& VB,
                                 const features::FeatureMatch& match, const Registration& registration,
                                 double pair_distance) {
  const auto& pa = match.points_a;
  const auto& pb = match.points_b;
  MatrixX3d xa(Index(pa.vertices.size()), 3), xb(Index(pb.vertices.size()), 3);
  for (Index i = 0; i < xa.rows(); ++i) xa.row(i) = VA.row(pa.vertices[i]);
  for (Index i = 0; i < xb.rows(); ++i) xb.row(i) = VB.row(pb.vertices[i]);
  xb = registration.warp(xb);
  const double diagonal = (VA.colwise().maxCoeff() - VA.colwise().minCoeff()).norm();
  const PointPairs near = pair_nearest_points(xa, pa.kinds, xb, pb.kinds, pair_distance * diagonal);
  RegisteredPairs out;
  for (std::size_t i = 0; i < near.pairs.size(); ++i) {
    out.pairs.push_back({pa.vertices[near.pairs[i][0]], pb.vertices[near.pairs[i][1]]});
    out.scores.push_back(near.distances[i] / diagonal);
  }
  return out;
}

MorphPairs morph_pairs(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                       const features::MatchOptions& match_options, bool register_surfaces,
                       const RegisterOptions& register_options, double pair_distance, Progress* progress) {
  MorphPairs out{features::match_features(VA, FA, VB, FB, match_options, progress),
                 std::nullopt, {}};
  if (register_surfaces) {
    out.registration = register_matched(VA, FA, VB, FB, out.match, register_options, progress);
    out.pairs = registered_pairs(VA, VB, out.match, *out.registration, pair_distance);
  } else {
    out.pairs.pairs = out.match.point_pairs;
    out.pairs.scores = out.match.point_scores;
  }
  return out;
}

}  // namespace paramorph::morph
