#include "pomdp_topo/heading_estimator.h"

#include "laser_features/chi_square.h"

#include <cmath>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {
constexpr double kQuarterTurn = 0.5 * kPi;
}

HeadingEstimator::HeadingEstimator(const HeadingEstimatorParams& params)
    : params_(params), theta_(0.0), variance_(params.initial_variance) {}

bool HeadingEstimator::reset(double theta, double variance) {
  if (!std::isfinite(theta) || !std::isfinite(variance) || variance < 0.0) return false;
  theta_ = normalizeAngle(theta);
  variance_ = variance;
  return true;
}

bool HeadingEstimator::predict(double dtheta, double distance, std::string* error) {
  if (!std::isfinite(dtheta) || !std::isfinite(distance) || distance < 0.0) {
    if (error) {
      *error = "HeadingEstimator::predict: refused dtheta = " + std::to_string(dtheta) + ", distance = " +
               std::to_string(distance) + " (non-finite, or a negative distance)";
    }
    return false;
  }
  // Prediction of the 1-D Kalman filter: theta_k+1 = theta_k + dtheta, P += q.
  theta_ = normalizeAngle(theta_ + dtheta);
  variance_ += params_.odometry_variance_per_rad * std::abs(dtheta) + params_.odometry_variance_per_m * distance;
  return true;
}

namespace {
/// `angle` less the nearest multiple of a quarter turn: in [-pi/4, pi/4].
double offQuarterTurns(double angle) {
  const double d = normalizeAngle(angle);
  return d - std::round(d / kQuarterTurn) * kQuarterTurn;
}
}  // namespace

double HeadingEstimator::innovation(double alpha) const {
  // axis + family + k pi/2 - (theta + alpha) for the family and k that make it smallest.
  double best = offQuarterTurns(params_.axis_angle - theta_ - alpha);
  for (size_t f = 1; f < families_.size(); ++f) {
    const double nu = offQuarterTurns(params_.axis_angle + families_[f] - theta_ - alpha);
    if (std::abs(nu) < std::abs(best)) best = nu;
  }
  return best;
}

bool HeadingEstimator::addWallFamily(double offset, double tolerance) {
  if (!std::isfinite(offset) || !std::isfinite(tolerance)) return false;
  const double f = offQuarterTurns(offset);
  for (double known : families_) {
    if (std::abs(offQuarterTurns(f - known)) <= tolerance) return false;
  }
  families_.push_back(f);
  return true;
}

HeadingEstimator::Result HeadingEstimator::update(const std::vector<LineObs>& lines) {
  Result result;
  const double gate = laser_features::chiSquareQuantile(params_.gate_probability, 1);
  const double max_alpha_variance = params_.max_alpha_sigma * params_.max_alpha_sigma;
  double nis_sum = 0.0;
  for (const LineObs& line : lines) {
    if (!std::isfinite(line.alpha) || !std::isfinite(line.alpha_variance) || !std::isfinite(line.length) ||
        line.alpha_variance < 0.0 || line.length < 0.0) {
      ++result.invalid;
      continue;
    }
    if (line.length < params_.min_line_length || line.alpha_variance > max_alpha_variance) {
      ++result.ignored;
      continue;
    }
    const double nu = innovation(line.alpha);
    const double S = variance_ + line.alpha_variance;  // H P H^T + R with H = -1
    if (!(S > 0.0)) {  // a perfect heading and a perfect line: nothing to learn
      ++result.ignored;
      continue;
    }
    const double nis = nu * nu / S;
    if (nis > gate) {  // chi^2 validation gate, 1 dof
      ++result.rejected;
      continue;
    }
    const double K = variance_ / S;
    theta_ = normalizeAngle(theta_ + K * nu);
    variance_ = (1.0 - K) * variance_;
    nis_sum += nis;
    ++result.used;
  }
  if (result.used > 0) result.mean_nis = nis_sum / result.used;
  return result;
}

void HeadingEstimator::shift(int quarter_turns) {
  theta_ = normalizeAngle(theta_ + double(quarter_turns % 4) * kQuarterTurn);
}

void HeadingRealigner::setTrusted(bool trusted) {
  trusted_ = trusted;
  last_ = 0;
  votes_ = 0;
}

int HeadingRealigner::update(int state_bin, int front_end_bin) {
  if (trusted_) return 0;
  const int k = ((state_bin - front_end_bin) % bins_ + bins_) % bins_;
  if (k != last_) {
    last_ = k;
    votes_ = 0;
  }
  if (++votes_ < updates_) return 0;
  votes_ = 0;
  if (k == 0) trusted_ = true;  // the belief has agreed with the heading long enough
  return k;
}

}  // namespace pomdp_topo
