// Shape signature (features/shape_signature.h, thesis 3.5.3).
#include "features/shape_signature.h"

#include <cmath>
#include <limits>
#include <string>

#include "common/errors.h"
#include "mesh/validate.h"
#include "param/spherical/sphere_map.h"
#include "param/spherical/sphere_quality.h"

namespace paramorph::features {

namespace {

/// Runs the sphere map inside [0, hi] of the caller's progress.
MatrixX3d conformal_sphere(const MatrixX3d& V, const MatrixX3i& F, Progress* progress, double hi) {
  spherical::SphereMapOptions conformal;
  conformal.keep_squeezed_start = true;  // the signature's histograms were measured on that map
  if (!progress) return spherical::sphere_map(V, F, conformal, nullptr).positions;
  Progress inner(
      [progress, hi](double fraction, const std::string& stage) {
        progress->report(hi * fraction, "sphere map: " + stage);  // throws Cancelled itself
        return true;
      },
      0.0);
  return spherical::sphere_map(V, F, conformal, &inner).positions;
}

/// Checks a histogram for signature_distance and returns its cumulative sums, normalised.
VectorXd normalised_cumulative(const VectorXd& h, const char* name) {
  PM_REQUIRE(h.size() > 0, InvalidInputError, "signature_distance: ", name, " is empty");
  PM_REQUIRE(h.allFinite(), InvalidInputError, "signature_distance: ", name,
             " has non-finite entries");
  PM_REQUIRE(h.minCoeff() >= 0.0, InvalidInputError, "signature_distance: ", name,
             " has negative entries (", h.minCoeff(), "); signatures are histograms");
  const double total = h.sum();
  PM_REQUIRE(total > 0.0, InvalidInputError, "signature_distance: ", name, " sums to 0");
  VectorXd cumulative(h.size());
  double running = 0.0;
  for (Eigen::Index k = 0; k < h.size(); ++k) cumulative[k] = (running += h[k] / total);
  return cumulative;
}

}  // namespace

VectorXd shape_signature(const MatrixX3d& V, const MatrixX3i& F, const SignatureOptions& options,
                         Progress* progress) {
  const int bins = options.bins;
  const double L = options.log_range;
  PM_REQUIRE(bins >= 1 && bins <= 1000000, InvalidInputError,
             "shape_signature: bins must be in [1, 1000000], got ", bins);
  PM_REQUIRE(std::isfinite(L) && L > 0.0, InvalidInputError,
             "shape_signature: log_range must be finite and > 0, got ", L);
  if (progress) progress->report(0.0, "shape signature");

  MatrixX3d sphere;
  if (options.sphere) {
    validate_arrays(V, F);
    sphere = *options.sphere;
    PM_REQUIRE(sphere.rows() == V.rows(), InvalidInputError, "shape_signature: sphere has ",
               sphere.rows(), " rows but the mesh has ", V.rows(), " vertices");
    PM_REQUIRE(sphere.allFinite(), InvalidInputError,
               "shape_signature: sphere has non-finite (NaN or inf) coordinates");
  } else {
    sphere = conformal_sphere(V, F, progress, 0.95);
  }

  const VectorXd surface = spherical::face_areas(V, F);
  const VectorXd mapped = spherical::face_areas(sphere, F);
  const double surface_total = surface.sum(), mapped_total = mapped.sum();
  PM_REQUIRE(surface_total > 0.0 && std::isfinite(surface_total), InvalidInputError,
             "shape_signature: the mesh has zero total area");
  PM_REQUIRE(mapped_total > 0.0 && std::isfinite(mapped_total), InvalidInputError,
             "shape_signature: the sphere map has zero total area");

  // Weight A_f / A at x = ln s_f, split between the bracketing bin centres
  // c_k = -L + (k + 1/2) w, i.e. at t = (x + L) / w - 1/2 in bin-centre units.
  const double width = 2.0 * L / bins;
  VectorXd histogram = VectorXd::Zero(bins);
  for (Index f = 0; f < Index(F.rows()); ++f) {
    const double weight = surface[f] / surface_total;
    if (weight <= 0.0) continue;  // contributes nothing (and ln 0 is -inf)
    const double share = mapped[f] / mapped_total;
    const double x =
        share > 0.0 ? std::log(weight / share) : std::numeric_limits<double>::infinity();
    const double t = (x + L) / width - 0.5;
    if (!(t > 0.0)) {
      histogram[0] += weight;
    } else if (t >= bins - 1) {
      histogram[bins - 1] += weight;
    } else {
      const int k = int(t);
      const double above = t - k;
      histogram[k] += (1.0 - above) * weight;
      histogram[k + 1] += above * weight;
    }
  }
  histogram /= histogram.sum();
  if (progress) progress->report(1.0, "shape signature");
  return histogram;
}

double signature_distance(const VectorXd& a, const VectorXd& b, double log_range) {
  PM_REQUIRE(a.size() == b.size(), InvalidInputError,
             "signature_distance: the signatures have different sizes (", a.size(), " and ",
             b.size(), " bins); compare signatures made with the same bins");
  PM_REQUIRE(std::isfinite(log_range) && log_range > 0.0, InvalidInputError,
             "signature_distance: log_range must be finite and > 0, got ", log_range);
  const VectorXd ca = normalised_cumulative(a, "the first signature");
  const VectorXd cb = normalised_cumulative(b, "the second signature");
  const double width = 2.0 * log_range / double(a.size());
  // The last cumulative sums are both 1: only the first size - 1 differ.
  return width * (ca - cb).head(a.size() - 1).cwiseAbs().sum();
}

}  // namespace paramorph::features
