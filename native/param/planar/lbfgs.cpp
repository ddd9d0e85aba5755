#include "param/planar/lbfgs.h"

#include <cmath>
#include <deque>
#include <limits>

#include "common/errors.h"

namespace paramorph::planar {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Sample {
  double t, f, slope;  // step, energy, directional derivative
};

/// Minimiser of the cubic through two samples, kept inside [lo + 10%, hi - 10%]
/// of the bracket (bisection when the cubic is unusable): the safeguard of
/// Brent's and Moré–Thuente's line searches.
double interpolate(const Sample& a, const Sample& b) {
  const double lo = std::min(a.t, b.t), hi = std::max(a.t, b.t), width = hi - lo;
  const double d1 = a.slope + b.slope - 3.0 * (a.f - b.f) / (a.t - b.t);
  const double disc = d1 * d1 - a.slope * b.slope;
  double t = 0.5 * (lo + hi);
  if (disc >= 0.0 && std::isfinite(a.f) && std::isfinite(b.f)) {
    const double d2 = std::copysign(std::sqrt(disc), b.t - a.t);
    const double candidate =
        b.t - (b.t - a.t) * (b.slope + d2 - d1) / (b.slope - a.slope + 2.0 * d2);
    if (std::isfinite(candidate)) t = candidate;
  }
  return std::clamp(t, lo + 0.1 * width, hi - 0.1 * width);
}

class LineSearch {
 public:
  LineSearch(const EnergyFunction& energy, const LbfgsOptions& o, LbfgsResult& stats)
      : energy_(energy), o_(o), stats_(stats) {}

  /// Strong Wolfe step along d in (0, t_cap]; returns false if none was found.
  bool run(const VectorXd& x, const VectorXd& d, const Sample& start, double t_cap,
           VectorXd& x_next, VectorXd& g_next, double& f_next) {
    x_ = &x;
    d_ = &d;
    start_ = start;
    Sample previous = start;
    double t = std::min(1.0, t_cap);
    for (int k = 0; k < o_.max_line_search_evaluations; ++k) {
      const Sample s = evaluate(t);
      if (!armijo(s) || (k > 0 && s.f >= previous.f))
        return zoom(previous, s, x_next, g_next, f_next);
      if (std::abs(s.slope) <= -o_.wolfe_c2 * start_.slope) return accept(x_next, g_next, f_next);
      if (s.slope >= 0.0) return zoom(s, previous, x_next, g_next, f_next);
      if (t >= t_cap) return accept(x_next, g_next, f_next);  // best feasible: the cap itself
      previous = s;
      t = std::min(2.0 * t, t_cap);
    }
    return false;
  }

 private:
  Sample evaluate(double t) {
    x_try_ = *x_ + t * *d_;
    f_try_ = energy_(x_try_, &g_try_);
    ++stats_.energy_evaluations;
    ++stats_.gradient_evaluations;
    return {t, f_try_, std::isfinite(f_try_) ? g_try_.dot(*d_) : kInfinity};
  }
  bool armijo(const Sample& s) const {
    return std::isfinite(s.f) && s.f <= start_.f + o_.wolfe_c1 * s.t * start_.slope;
  }
  bool accept(VectorXd& x_next, VectorXd& g_next, double& f_next) {
    x_next = x_try_;  // the last evaluated point is the accepted one
    g_next = g_try_;
    f_next = f_try_;
    return true;
  }
  /// lo satisfies Armijo and has the lower energy; the minimiser lies between lo and hi.
  bool zoom(Sample lo, Sample hi, VectorXd& x_next, VectorXd& g_next, double& f_next) {
    for (int k = 0; k < o_.max_line_search_evaluations; ++k) {
      const Sample s = evaluate(interpolate(lo, hi));
      if (!armijo(s) || s.f >= lo.f) {
        hi = s;
      } else {
        if (std::abs(s.slope) <= -o_.wolfe_c2 * start_.slope) return accept(x_next, g_next, f_next);
        if (s.slope * (hi.t - lo.t) >= 0.0) hi = lo;
        lo = s;
      }
      if (std::abs(hi.t - lo.t) <= 1e-12 * std::max(1.0, lo.t)) break;
    }
    if (lo.t > 0.0 && lo.f < start_.f) {  // no Wolfe point, but a strict decrease
      evaluate(lo.t);
      return accept(x_next, g_next, f_next);
    }
    return false;
  }

  const EnergyFunction& energy_;
  const LbfgsOptions& o_;
  LbfgsResult& stats_;
  const VectorXd* x_ = nullptr;
  const VectorXd* d_ = nullptr;
  Sample start_{};
  VectorXd x_try_, g_try_;
  double f_try_ = kInfinity;
};

}  // namespace

LbfgsResult minimize_lbfgs(const EnergyFunction& energy, const StepBound& max_step, VectorXd& x,
                           const LbfgsOptions& o, ProgressWindow progress,
                           const LbfgsPreconditioner& preconditioner) {
  PM_REQUIRE(o.memory > 0 && o.max_iterations >= 0 && o.energy_window >= 1 && o.feasible_fraction > 0 &&
                 o.feasible_fraction < 1 && 0 < o.wolfe_c1 && o.wolfe_c1 < o.wolfe_c2 &&
                 o.wolfe_c2 < 1,
             InvalidInputError, "invalid L-BFGS options");
  LbfgsResult result;
  VectorXd g;
  double f = energy(x, &g);
  ++result.energy_evaluations;
  ++result.gradient_evaluations;
  PM_REQUIRE(std::isfinite(f), ConstraintError, "L-BFGS needs a fold-free start (energy is ", f, ")");
  result.energy_history.push_back(f);
  const double g0 = o.gradient_reference > 0 ? o.gradient_reference : std::max(1.0, g.norm());
  std::deque<std::pair<VectorXd, VectorXd>> pairs;  // (s, y), newest last
  std::vector<double> alpha(o.memory);
  LineSearch search(energy, o, result);
  VectorXd d, x_next, g_next;
  bool plain_gradient = false;  // this step ignores the preconditioner (a fallback)
  double pair_scale = 1.0;  // sᵀPs / sᵀy of the newest pair, with a preconditioner
  result.stop_reason = "max_iterations";
  while (result.iterations < o.max_iterations) {
    if (g.norm() <= o.gradient_tol * g0) {
      result.stop_reason = "gradient";
      break;
    }
    // Two-loop recursion: d = -H g.
    d = -g;
    for (int i = int(pairs.size()) - 1; i >= 0; --i) {
      alpha[i] = pairs[i].first.dot(d) / pairs[i].second.dot(pairs[i].first);
      d -= alpha[i] * pairs[i].second;
    }
    if (preconditioner.apply && !plain_gradient) {
      preconditioner.apply(d);
      if (!pairs.empty()) d *= pair_scale;
    } else if (!pairs.empty()) {
      const auto& [s, y] = pairs.back();
      d *= s.dot(y) / y.dot(y);
    }
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const double rho = 1.0 / pairs[i].second.dot(pairs[i].first);
      const double beta = rho * pairs[i].second.dot(d);
      d += (alpha[i] - beta) * pairs[i].first;
    }
    double slope = g.dot(d);
    if (!(slope < 0.0)) {  // not a descent direction: restart from steepest descent
      pairs.clear();
      d = -g;
      slope = -g.squaredNorm();
    }
    const double t_cap = o.feasible_fraction * max_step(x, d);
    double f_next = 0.0;
    if (!(t_cap > 0.0) || !search.run(x, d, {0.0, f, slope}, t_cap, x_next, g_next, f_next)) {
      // Retry from the last resort first: without pairs, then (when
      // preconditioned) the plain gradient, whose first steps are tiny but
      // safe where a barrier makes the Laplacian's shape misleading.
      if (pairs.empty() && (plain_gradient || !preconditioner.apply)) {
        result.stop_reason = "line_search";
        break;
      }
      plain_gradient = pairs.empty();
      pairs.clear();
      continue;
    }
    plain_gradient = false;
    VectorXd s = x_next - x, y = g_next - g;
    if (s.dot(y) > 1e-16 * s.norm() * y.norm()) {  // keep H positive definite
      if (preconditioner.quadratic) pair_scale = preconditioner.quadratic(s) / s.dot(y);
      pairs.emplace_back(std::move(s), std::move(y));
      if (int(pairs.size()) > o.memory) pairs.pop_front();
    }
    x.swap(x_next);
    g.swap(g_next);
    f = f_next;
    ++result.iterations;
    result.energy_history.push_back(f);
    progress.report(double(result.iterations) / o.max_iterations, "l-bfgs");
    const int k = result.iterations;  // energy_history[k] is f
    if (k >= o.energy_window &&
        result.energy_history[k - o.energy_window] - f < o.energy_tol * std::abs(f)) {
      result.stop_reason = "energy";
      break;
    }
  }
  return result;
}

}  // namespace paramorph::planar
