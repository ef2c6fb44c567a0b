// Heading estimation from the building's axes (Tomatis et al. 2001, section 3.3): "a Kalman filter
// on theta alone", updated with the lines that are parallel or perpendicular to the axes of a
// rectilinear building, each validated with the chi^2 gate of 1 degree of freedom.
//
// State: the robot's heading theta in the map frame (normalized to (-pi, pi]) and its variance P.
//   predict:  theta += dtheta,  P += q,  q = q_rad |dtheta| + q_m distance
//   update, per usable line with normal alpha (robot frame, (alpha, r) model of Arras & Siegwart):
//     the wall's normal in the map frame is theta + alpha, expected at axis_angle + k pi/2;
//     nu = normalizeAngle(axis_angle + k pi/2 - (theta + alpha)) for the nearest k (|nu| <= pi/4),
//     h(theta) = -theta + const, so H = -1 and with the sign folded into nu:
//     S = P + sigma_alpha^2,  gate nu^2 / S <= chi2_1(gate_probability),
//     K = P / S,  theta += K nu,  P = (1 - K) P          (scalar Kalman update, applied sequentially)
//
// Consistency: with every good line used the mean NEES is ~1 (test_heading_estimator). The 95% gate
// also drops ~5% of good lines, preferentially those with a large error behind them while P stays
// unchanged, so on clean data the filter is somewhat overconfident (mean NEES 1.1-1.4 measured);
// a gate_probability of 0.999 restores consistency at the price of accepting lines nearer the axes.
//
// Wings: a wing's walls run 30-60 deg off the building's axes. Its direction, learnt while its
// hallway is followed with a heading known to better than the walls' parallel tolerance
// (addWallFamily, from the front end), is a wall family of its own, and a line is compared with the
// nearest family. Without it the wing's walls are only rejected, the variance grows with every turn
// in the wing's rooms, and once it covers the wing's angle the gate takes a wing wall for an axis
// wall and turns the heading by that angle.
//
// The gate needs the prior variance to cover the actual error: after a kidnapping, reset() with a
// variance that covers it (or shift() by quarter turns once the topological belief knows better).
//
// ROS-free: the standard library and laser_features only.
#pragma once

#include "laser_features/building_axes.h"

#include <string>
#include <vector>

namespace pomdp_topo {

/// Parameters of HeadingEstimator (each with its unit and default).
struct HeadingEstimatorParams {
  double axis_angle = 0.0;                  // rad, direction of the building's axes in the map frame;
                                            // wall normals are expected at axis_angle + k pi/2
  double gate_probability = 0.95;           // -, chi^2 validation gate, 1 degree of freedom
  double odometry_variance_per_rad = 0.0025;  // rad^2 per rad turned (|dtheta|)
  double odometry_variance_per_m = 1e-4;    // rad^2 per m travelled
  double min_line_length = 1.0;             // m, shorter lines are not used
  double initial_variance = 0.01;           // rad^2, variance of the heading at construction
  double max_alpha_sigma = 0.1;             // rad, lines with a larger sigma_alpha are not used
};

class HeadingEstimator {
 public:
  /// A line seen by the robot, robot frame.
  struct LineObs {
    double alpha = 0.0;           // rad, direction of the line's normal in the robot frame
    double alpha_variance = 0.0;  // rad^2, sigma_alpha^2 (the (0, 0) entry of the line's covariance)
    double length = 0.0;          // m, of the segment the scan saw
  };
  /// The line of a laser_features LineSegment (already in the robot frame) as an observation.
  static LineObs fromLine(const laser_features::Line& line, double length) {
    return {line.alpha, line.cov(0, 0), length};
  }

  /// What update() did with the lines it was given.
  struct Result {
    int used = 0;         // passed the gate and updated the heading
    int rejected = 0;     // failed the chi^2 gate (furniture, clutter, or a wrong heading)
    int ignored = 0;      // shorter than min_line_length or sigma_alpha above max_alpha_sigma
    int invalid = 0;      // NaN/inf alpha, variance or length, or a negative variance or length
    double mean_nis = 0.0;  // mean normalized innovation squared nu^2 / S of the used lines (0 if none)
  };

  explicit HeadingEstimator(const HeadingEstimatorParams& params = {});

  /// Sets theta (normalized) and P. Returns false and changes nothing for a non-finite theta or a
  /// non-finite or negative variance.
  bool reset(double theta, double variance);

  /// Odometry: theta += dtheta, P += odometry_variance_per_rad |dtheta| + odometry_variance_per_m
  /// distance. Refuses (false, `error` set, state unchanged) non-finite inputs or a negative distance.
  bool predict(double dtheta, double distance, std::string* error = nullptr);

  /// Sequential gated Kalman updates with every usable line (see the file comment).
  Result update(const std::vector<LineObs>& lines);

  /// Re-aligns theta by quarter_turns * pi/2 (P unchanged): the topological belief decided that the
  /// estimate is off by a multiple of 90 degrees (e.g. after a kidnapping).
  void shift(int quarter_turns);

  double theta() const { return theta_; }
  double variance() const { return variance_; }
  const HeadingEstimatorParams& params() const { return params_; }
  /// The building's axis (rad, map frame) the walls are expected along, once it is known.
  void setAxis(double axis_angle) { params_.axis_angle = axis_angle; }

  /// The innovation of a line against the nearest wall direction (the axes, or a wing's) for the
  /// current theta, in [-pi/4, pi/4].
  double innovation(double alpha) const;

  /// A wing's walls run at `offset` (rad, taken modulo pi/2) to the axes: walls along it are
  /// expected from now on. Not added (false) within `tolerance` (rad) of a known family.
  bool addWallFamily(double offset, double tolerance);
  /// rad, the wall directions' offsets to the axes, in (-pi/4, pi/4]; 0 (the axes) first.
  const std::vector<double>& wallFamilies() const { return families_; }

 private:
  HeadingEstimatorParams params_;
  double theta_ = 0.0;
  double variance_ = 0.0;
  std::vector<double> families_{0.0};
};

/// When the front end's heading is turned by whole bins to the topological belief's (after a
/// kidnapping, or on a loaded map whose frame is not the odometry's): when a confident belief keeps
/// one other heading for `updates` updates in a row. While the dead-reckoned heading is trusted (a
/// map built in this run, no jump since, or a heading the belief has since agreed with for `updates`
/// updates), it is not second-guessed: a disagreeing belief is then the wrong one (large_floor: a
/// re-alignment by a quarter turn after a U-turn at a hallway end sent the robot out of the next
/// room facing the wall, and the belief was lost).
class HeadingRealigner {
 public:
  HeadingRealigner(int bins, int updates) : bins_(bins > 0 ? bins : 1), updates_(updates) {}

  /// trusted: the dead-reckoned heading is the map's (votes start over).
  void setTrusted(bool trusted);
  bool trusted() const { return trusted_; }

  /// One confident belief update: the bin of its most likely state and the front end's bin. Returns
  /// the bins to turn the front end by (0: none). `updates` agreeing updates make the heading trusted.
  int update(int state_bin, int front_end_bin);

 private:
  int bins_;
  int updates_;
  bool trusted_ = false;
  int last_ = 0;   // the disagreement (bins) of the updates counted
  int votes_ = 0;  // confident updates in a row with that disagreement
};

}  // namespace pomdp_topo
