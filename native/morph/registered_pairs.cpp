#include "morph/registered_pairs.h"

#include <Eigen/Geometry>

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

double carried_fold_share(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB,
                          const MatrixX3i& FB, const ClosestPoints& on_a) {
  double folded = 0, total = 0;
  for (Index f = 0; f < FB.rows(); ++f) {
    const Eigen::Vector3d b0 = VB.row(FB(f, 0)), b1 = VB.row(FB(f, 1)), b2 = VB.row(FB(f, 2));
    const double area = (b1 - b0).cross(b2 - b0).norm();
    const Eigen::Vector3d q0 = on_a.points.row(FB(f, 0)), q1 = on_a.points.row(FB(f, 1)),
                          q2 = on_a.points.row(FB(f, 2));
    const Index fa = on_a.face[FB(f, 0)];
    const Eigen::Vector3d a0 = VA.row(FA(fa, 0)), a1 = VA.row(FA(fa, 1)), a2 = VA.row(FA(fa, 2));
    if ((q1 - q0).cross(q2 - q0).dot((a1 - a0).cross(a2 - a0)) <= 0) folded += area;
    total += area;
  }
  return total > 0 ? folded / total : 0.0;
}

MorphPairs morph_pairs(const MatrixX3d& VA, const MatrixX3i& FA, const MatrixX3d& VB, const MatrixX3i& FB,
                       const features::MatchOptions& match_options, bool register_surfaces,
                       const RegisterOptions& register_options, double pair_distance, double max_fold_share,
                       Progress* progress) {
  MorphPairs out{features::match_features(VA, FA, VB, FB, match_options, progress), std::nullopt, {}, 0, {}};
  if (register_surfaces) {
    Registration registration = register_matched(VA, FA, VB, FB, out.match, register_options, progress);
    const MatrixX3d registered = registration.warp(VB);
    ClosestPoints on_a = ClosestPointTree(VA, FA).query(registered);
    out.fold_share = carried_fold_share(VA, FA, registered, FB, on_a);
    if (out.fold_share <= max_fold_share) {
      out.pairs = registered_pairs(VA, VB, out.match, registration, pair_distance);
      out.registration = std::move(registration);
      out.on_a = std::move(on_a);
      return out;
    }
  }
  {
    out.pairs.pairs = out.match.point_pairs;
    out.pairs.scores = out.match.point_scores;
  }
  return out;
}

}  // namespace paramorph::morph
