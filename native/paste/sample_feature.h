// Reading a feature back (thesis 5.2: the detail is rebuilt as the base
// surface offset by the stored displacement): at uv points of the feature's
// domain, the base position and local frame (through the base map) and the
// displacement (bilinear from the grid), all in the feature frame.
// extract_feature computes its grid with the same base and frame lookups, so
// at a grid node the rebuilt point is the feature's own point.
#pragma once

#include "paste/feature.h"

namespace paramorph::paste {

struct BaseSample {
  MatrixX3d base;          ///< #Q by 3: base surface B(uv), feature frame
  MatrixX3d e_u, e_v, n;   ///< #Q by 3 each: the base's local frame there (paste/map_frames.h)
  VectorXd distance;       ///< #Q: 0 inside the domain, else the distance to it (values from its closest point)
};

/// The base part alone at uv (#Q by 2): extract_feature's grid uses it, so
/// lookup and extraction agree.
BaseSample sample_base(const Feature& feature, const MatrixX2d& uv);

struct FeatureSample {
  MatrixX3d base;          ///< #Q by 3: base surface B(uv), feature frame
  MatrixX3d e_u, e_v, n;   ///< #Q by 3 each: the base's local frame there
  MatrixX3d displacement;  ///< #Q by 3: bilinear from the grid (components along e_u, e_v, n)
  MatrixX3d position;      ///< #Q by 3: base + [e_u e_v n] displacement, feature frame
  VectorXd distance;       ///< #Q: 0 inside the domain, else the distance to it (values from its closest point)
};

/// uv: #Q by 2 points in the feature's domain.
FeatureSample sample_feature(const Feature& feature, const MatrixX2d& uv);

/// Bilinear lookup of the displacement grid at uv (#Q by 2): #Q by 3. Points
/// off the grid are clamped to its square.
MatrixX3d bilinear_displacement(const Feature& feature, const MatrixX2d& uv);

}  // namespace paramorph::paste
