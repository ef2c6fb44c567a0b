#include "ekf_local_map/stochastic_map.h"
#include "symmetric.h"

#include "laser_features/chi_square.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace ekf_local_map {

using laser_features::compose;
using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {

/// The point of the segment [a, b] closest to p.
Eigen::Vector2d closestPointOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double t = length_sq > 0.0 ? std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

/// Range at which the ray from the origin through `direction` (unit) crosses the segment [a, b];
/// +infinity when it does not.
double rayHitsSegment(const Eigen::Vector2d& direction, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  // t d = a + u (b - a), t > 0, u in [0, 1]: Cramer's rule with 2D cross products.
  const Eigen::Vector2d ab = b - a;
  const double denominator = laser_features::cross2(direction, ab);
  if (std::abs(denominator) < 1e-12) return std::numeric_limits<double>::infinity();
  const double t = laser_features::cross2(a, ab) / denominator;
  const double u = laser_features::cross2(a, direction) / denominator;
  return (t > 0.0 && u >= 0.0 && u <= 1.0) ? t : std::numeric_limits<double>::infinity();
}

}  // namespace

const char* toString(ObservationOutcome outcome) {
  switch (outcome) {
    case ObservationOutcome::kMatched: return "matched";
    case ObservationOutcome::kNewLine: return "new line";
    case ObservationOutcome::kRejectedNotFinite: return "rejected: not finite";
    case ObservationOutcome::kRejectedCovarianceNotPD: return "rejected: covariance not positive definite";
    case ObservationOutcome::kOutOfGate: return "out of gate";
    case ObservationOutcome::kAmbiguous: return "ambiguous";
  }
  return "unknown";
}

const char* toString(RelocationResult::Verdict verdict) {
  switch (verdict) {
    case RelocationResult::Verdict::kSuccess: return "success";
    case RelocationResult::Verdict::kTooFewMatches: return "too few lines matched";
    case RelocationResult::Verdict::kJointlyIncompatible: return "matches jointly incompatible";
    case RelocationResult::Verdict::kParallelLines: return "matched lines (nearly) parallel";
  }
  return "unknown";
}

void UpdateReport::clear() {
  observations = matched = new_lines = 0;
  rejected_not_finite = rejected_not_positive_definite = out_of_gate = ambiguous = 0;
  expected_lines = 0;
  mean_nis = joint_nis = 0.0;
  gating_failure = fused = relocation_attempted = false;
  relocation = RelocationResult();
  outcomes.clear();
  matches.clear();
}

// ---------------------------------------------------------------------------------------------
// Storage

StochasticMap::StochasticMap(const Params& params) : params_(params) {
  ensureLineCapacity(std::max<size_t>(params_.initial_line_capacity, 1));
  x_.setZero();
  P_.setZero();
}

void StochasticMap::ensureLineCapacity(size_t lines) {
  if (lines <= line_capacity_ && x_.size() > 0) return;
  const size_t capacity = std::max(lines, 2 * line_capacity_);
  const Eigen::Index dim = Eigen::Index(3 + 2 * capacity);
  const Eigen::Index used = x_.size() > 0 ? Eigen::Index(stateSize()) : 0;

  Eigen::VectorXd x = Eigen::VectorXd::Zero(dim);
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(dim, dim);
  if (used > 0) {
    x.head(used) = x_.head(used);
    P.topLeftCorner(used, used) = P_.topLeftCorner(used, used);
  }
  x_.swap(x);
  P_.swap(P);
  robot_columns_.resize(dim, 3);
  W_.setZero(dim + kUpdateKernelRowPadding, std::max<Eigen::Index>(W_.cols(), 2));  // rows below the state: see applyStackedUpdate
  line_capacity_ = capacity;
  extents_.reserve(capacity);
  predictions_.reserve(capacity);
  line_taken_.reserve(capacity);
}

void StochasticMap::ensureMatchCapacity(size_t matches) {
  const Eigen::Index needed = Eigen::Index(2 * matches);
  if (needed <= W_.cols() && needed <= S_.rows()) return;
  const Eigen::Index cols = std::max<Eigen::Index>({needed, 2 * W_.cols(), 20});
  W_.setZero(x_.size() + kUpdateKernelRowPadding, cols);
  S_.resize(cols, cols);
  nu_.resize(cols);
  inv_diag_.resize(cols);
  match_jacobians_.reserve(size_t(cols / 2));
}

// ---------------------------------------------------------------------------------------------
// State access (P_ holds the lower triangle)

Eigen::Matrix3d StochasticMap::robotCovariance() const {
  return P_.topLeftCorner<3, 3>().selfadjointView<Eigen::Lower>();
}

Eigen::Matrix2d StochasticMap::lineBlock(size_t i) const {
  return P_.block<2, 2>(Eigen::Index(lineIndex(i)), Eigen::Index(lineIndex(i))).selfadjointView<Eigen::Lower>();
}

MapLine StochasticMap::line(size_t i) const {
  MapLine line;
  line.line.alpha = x_(Eigen::Index(lineIndex(i)));
  line.line.r = x_(Eigen::Index(lineIndex(i) + 1));
  line.line.cov = lineBlock(i);
  line.extent_start = extents_[i].start;
  line.extent_end = extents_[i].end;
  return line;
}

Eigen::Matrix2d StochasticMap::lineCrossCovariance(size_t i, size_t j) const {
  const Eigen::Index li = Eigen::Index(lineIndex(i)), lj = Eigen::Index(lineIndex(j));
  if (i > j) return P_.block<2, 2>(li, lj);
  return P_.block<2, 2>(lj, li).transpose();
}

Eigen::MatrixXd StochasticMap::covariance() const {
  const Eigen::Index n = Eigen::Index(stateSize());
  return P_.topLeftCorner(n, n).selfadjointView<Eigen::Lower>();
}

double StochasticMap::robotNees(const Pose2D& true_pose) const {
  const Pose2D estimate = robotPose();
  const Eigen::Vector3d e(estimate.x - true_pose.x, estimate.y - true_pose.y,
                          normalizeAngle(estimate.theta - true_pose.theta));
  const Eigen::LLT<Eigen::Matrix3d> llt(robotCovariance());
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  return e.dot(llt.solve(e));
}

double StochasticMap::lineNees(size_t i, const Line& true_line) const {
  const MapLine estimate = line(i);
  // lineDifference(estimate, truth) is the estimate minus one representation of the (constant)
  // truth: its covariance is the estimate's, whichever representation it took.
  return mahalanobisSq(laser_features::lineDifference(estimate.line, true_line), estimate.line.cov);
}

bool StochasticMap::setState(const Pose2D& robot, const std::vector<MapLine>& lines,
                             const Eigen::MatrixXd& P, bool relocation_pending) {
  const Eigen::Index n = Eigen::Index(3 + 2 * lines.size());
  if (P.rows() != n || P.cols() != n) return false;
  ensureLineCapacity(lines.size());
  x_.setZero();
  x_(0) = robot.x;
  x_(1) = robot.y;
  x_(2) = robot.theta;
  extents_.clear();
  for (size_t i = 0; i < lines.size(); ++i) {
    x_(Eigen::Index(lineIndex(i))) = lines[i].line.alpha;
    x_(Eigen::Index(lineIndex(i) + 1)) = lines[i].line.r;
    extents_.push_back({lines[i].extent_start, lines[i].extent_end});
  }
  P_.setZero();
  P_.topLeftCorner(n, n).triangularView<Eigen::Lower>() = P.triangularView<Eigen::Lower>();
  relocation_pending_ = relocation_pending;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Eqs. 7–8: prediction, O(n)

bool StochasticMap::predict(const Pose2D& odom_increment, const Eigen::Matrix3d& increment_cov) {
  if (!std::isfinite(odom_increment.x) || !std::isfinite(odom_increment.y) ||
      !std::isfinite(odom_increment.theta) || !increment_cov.allFinite()) {
    return false;  // a bad increment must not poison the state
  }
  Eigen::Matrix3d F, G;
  const Pose2D moved = predictRobotPose(robotPose(), odom_increment, &F, &G);  // eq. 7
  // eq. 8: P_rr <- F P_rr F^T + G U G^T, P_mr <- P_mr F^T (P_mm is unchanged)
  const Eigen::Matrix3d P_rr = robotCovariance();
  const Eigen::Matrix3d moved_cov = F * P_rr * F.transpose() + G * symmetric<3>(increment_cov) * G.transpose();
  P_.topLeftCorner<3, 3>() = symmetric<3>(moved_cov);
  const Eigen::Index m = Eigen::Index(stateSize()) - 3;
  if (m > 0) {
    robot_columns_.topRows(m).noalias() = P_.block(3, 0, m, 3) * F.transpose();
    P_.block(3, 0, m, 3) = robot_columns_.topRows(m);
  }
  x_(0) = moved.x;
  x_(1) = moved.y;
  x_(2) = moved.theta;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Relocation

bool StochasticMap::relocate(const Pose2D& pose_in_place, const Eigen::Matrix3d& cov) {
  if (!std::isfinite(pose_in_place.x) || !std::isfinite(pose_in_place.y) ||
      !std::isfinite(pose_in_place.theta) || !cov.allFinite()) {
    return false;
  }
  x_(0) = pose_in_place.x;
  x_(1) = pose_in_place.y;
  x_(2) = normalizeAngle(pose_in_place.theta);
  P_.topLeftCorner<3, 3>() = symmetric<3>(cov);
  const Eigen::Index m = Eigen::Index(stateSize()) - 3;
  if (m > 0) P_.block(3, 0, m, 3).setZero();  // the robot's past in this place is forgotten
  relocation_pending_ = true;
  return true;
}

uint32_t StochasticMap::countExpectedLines(const std::vector<LineSegment>& observations,
                                          const Pose2D& sensor_pose) const {
  const Pose2D to_sensor = laser_features::inverse(sensor_pose);
  uint32_t expected = 0;
  for (size_t i = 0; i < numLines(); ++i) {
    // The line's closest known point, in the sensor frame; hidden if an observed segment crosses
    // the ray to it clearly nearer (no visibility model beyond that: the laser sees 360 degrees).
    const Eigen::Vector2d closest = laser_features::transformPoint(
        to_sensor, closestPointOnSegment(sensor_pose.translation(), extents_[i].start, extents_[i].end));
    const double range = closest.norm();
    if (!(range > 0.0) || range > params_.expected_line_range) continue;
    const Eigen::Vector2d direction = closest / range;
    bool hidden = false;
    for (size_t j = 0; j < observations.size() && !hidden; ++j) {
      if (!observation_data_[j].valid) continue;
      hidden = rayHitsSegment(direction, observations[j].start, observations[j].end) < range - params_.occlusion_margin;
    }
    expected += hidden ? 0 : 1;
  }
  return expected;
}

RelocationResult StochasticMap::evaluateRelocation(const UpdateReport& report) const {
  RelocationResult result;
  result.matched = uint32_t(report.matches.size());
  result.joint_nis = report.joint_nis;
  for (size_t a = 0; a < report.matches.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      result.angle_span = std::max(result.angle_span,
                                   laser_features::angleBetweenLines(line(report.matches[a].line).line,
                                                                     line(report.matches[b].line).line));
    }
  }
  if (result.matched < std::max<uint32_t>(params_.relocation_min_matches, 1)) {
    result.verdict = RelocationResult::Verdict::kTooFewMatches;
    return result;
  }
  result.joint_nis_bound = laser_features::chiSquareQuantile(params_.relocation_joint_probability, int(2 * result.matched));
  if (!(report.joint_nis <= result.joint_nis_bound)) {
    result.verdict = RelocationResult::Verdict::kJointlyIncompatible;
  } else if (result.angle_span < params_.relocation_min_angle) {
    result.verdict = RelocationResult::Verdict::kParallelLines;
  } else {
    result.verdict = RelocationResult::Verdict::kSuccess;
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Eqs. 12–17: update

void StochasticMap::update(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
                           UpdateReport* report_out) {
  UpdateReport& report = report_out ? *report_out : scratch_report_;
  report.clear();
  report.observations = uint32_t(observations.size());
  report.outcomes.assign(observations.size(), ObservationOutcome::kOutOfGate);
  prepareObservations(observations, &report);
  line_taken_.assign(numLines(), 0);

  // First pass against the prior.
  const bool stacked = associate(observations, sensor_in_robot, &report);
  uint32_t valid = 0;
  for (const ObservationData& data : observation_data_) valid += data.valid ? 1 : 0;

  if (report.matches.empty()) {
    report.expected_lines = countExpectedLines(observations, compose(robotPose(), sensor_in_robot));
    // Lines were predicted within sight and lines were seen, but none matched: the pose is not
    // where the filter believes (odometry jump, kidnapping). Leave the state alone.
    report.gating_failure = report.expected_lines >= params_.gating_failure_min_expected &&
                            valid >= params_.gating_failure_min_observations;
    if (relocation_pending_) {
      report.relocation_attempted = true;
      report.relocation = evaluateRelocation(report);
    }
  } else if (stacked) {
    report.joint_nis = batch_nis_;
    bool fuse = true;
    if (relocation_pending_) {
      report.relocation_attempted = true;
      report.relocation = evaluateRelocation(report);
      fuse = report.relocation.success();
    }
    if (fuse) {
      applyStackedUpdate();  // eqs. 15–17
      report.fused = true;
      relocation_pending_ = false;
      growExtents(observations, sensor_in_robot, report, 0);
      // Second pass: the observations still unmatched, against the posterior. A common pose error
      // (a rare large odometry error) can push a re-observation beyond even the exclusion gate of
      // the prior; once the other matches have corrected the pose it matches again instead of
      // becoming a duplicate line. Sequential fusion is exact: the observations are independent.
      const size_t first = report.matches.size();
      const bool unmatched_left = std::any_of(report.outcomes.begin(), report.outcomes.end(), [](ObservationOutcome o) {
        return o == ObservationOutcome::kOutOfGate || o == ObservationOutcome::kAmbiguous;
      });
      if (unmatched_left && associate(observations, sensor_in_robot, &report)) {
        report.joint_nis += batch_nis_;  // NIS of the second batch given the first: the sum is the joint NIS
        applyStackedUpdate();
        growExtents(observations, sensor_in_robot, report, first);
      }
    }
  }
  summarizeMatches(&report);
  if (!report.gating_failure && !report.relocation_attempted && !relocation_pending_) {
    addNewLines(observations, sensor_in_robot, &report);  // eqs. 9–11
  }

  for (const ObservationOutcome outcome : report.outcomes) {
    switch (outcome) {
      case ObservationOutcome::kRejectedNotFinite: ++report.rejected_not_finite; break;
      case ObservationOutcome::kRejectedCovarianceNotPD: ++report.rejected_not_positive_definite; break;
      case ObservationOutcome::kOutOfGate: ++report.out_of_gate; break;
      case ObservationOutcome::kAmbiguous: ++report.ambiguous; break;
      default: break;
    }
  }
}

}  // namespace ekf_local_map
