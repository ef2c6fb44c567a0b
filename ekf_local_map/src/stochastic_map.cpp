#include "ekf_local_map/stochastic_map.h"

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

/// (A + A^T) / 2 of a small fixed-size matrix.
template <int N>
Eigen::Matrix<double, N, N> symmetric(const Eigen::Matrix<double, N, N>& A) {
  return 0.5 * (A + A.transpose());
}

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

void StochasticMap::prepareObservations(const std::vector<LineSegment>& observations, UpdateReport* report) {
  observation_data_.resize(observations.size());
  const double floor_alpha = params_.observation_alpha_sigma_floor, floor_r = params_.observation_r_sigma_floor;
  const Eigen::Matrix2d floor = Eigen::Vector2d(floor_alpha * floor_alpha, floor_r * floor_r).asDiagonal();
  for (size_t j = 0; j < observations.size(); ++j) {
    ObservationData& data = observation_data_[j];
    data.valid = false;
    data.in_exclusion_gate = false;
    switch (checkObservation(observations[j])) {
      case ObservationDefect::kNotFinite:
        report->outcomes[j] = ObservationOutcome::kRejectedNotFinite;
        continue;
      case ObservationDefect::kCovarianceNotPositiveDefinite:
        report->outcomes[j] = ObservationOutcome::kRejectedCovarianceNotPD;
        continue;
      case ObservationDefect::kNone:
        break;
    }
    data.valid = true;
    data.R = params_.observation_cov_inflation * symmetric<2>(observations[j].line.cov) + floor;
  }
}

void StochasticMap::placeSegments(const std::vector<LineSegment>& observations, const Pose2D& sensor_pose) {
  for (size_t j = 0; j < observations.size(); ++j) {
    ObservationData& data = observation_data_[j];
    if (!data.valid) continue;
    data.start_in_place = laser_features::transformPoint(sensor_pose, observations[j].start);
    data.end_in_place = laser_features::transformPoint(sensor_pose, observations[j].end);
  }
}

void StochasticMap::predictLines(const SensorPose& sensor) {
  const Eigen::Matrix3d P_rr = robotCovariance();
  predictions_.resize(numLines());
  for (size_t i = 0; i < numLines(); ++i) {
    LinePrediction& p = predictions_[i];
    const Line map_line{x_(Eigen::Index(lineIndex(i))), x_(Eigen::Index(lineIndex(i) + 1)), Eigen::Matrix2d::Zero()};
    p.h = predictLineInSensor(map_line, sensor, &p.H_line, &p.H_robot);  // eq. 12
    // H P H^T over the robot and line blocks (eq. 14 without R).
    const Eigen::Matrix<double, 2, 3> P_lr = P_.block<2, 3>(Eigen::Index(lineIndex(i)), 0);
    const Eigen::Matrix2d cross = p.H_line * P_lr * p.H_robot.transpose();
    p.HPHt = p.H_robot * P_rr * p.H_robot.transpose() + cross + cross.transpose() +
             p.H_line * lineBlock(i) * p.H_line.transpose();
  }
}

bool StochasticMap::extentsOverlap(size_t i, const ObservationData& observation) const {
  const double alpha = x_(Eigen::Index(lineIndex(i)));
  const Eigen::Vector2d direction(-std::sin(alpha), std::cos(alpha));  // along the line (Line::direction)
  const double e0 = direction.dot(extents_[i].start), e1 = direction.dot(extents_[i].end);
  const double t0 = direction.dot(observation.start_in_place), t1 = direction.dot(observation.end_in_place);
  const double gap = std::max(std::min(t0, t1) - std::max(e0, e1), std::min(e0, e1) - std::max(t0, t1));
  return gap <= params_.extent_margin;
}

void StochasticMap::findCandidates(const std::vector<LineSegment>& observations, const UpdateReport& report) {
  // Pairs between the validation gate and the wider exclusion gate are candidates too: the joint
  // test may accept them (see selectJointlyCompatible).
  const double exclusion = std::max(laser_features::chiSquareQuantile(params_.gate_probability, 2), params_.new_line_exclusion_nis);
  candidates_.clear();
  for (size_t j = 0; j < observations.size(); ++j) {
    ObservationData& data = observation_data_[j];
    if (!data.valid || report.outcomes[j] == ObservationOutcome::kMatched) continue;
    data.in_exclusion_gate = false;
    for (size_t i = 0; i < numLines(); ++i) {
      const LinePrediction& p = predictions_[i];
      // Cheap rejection first: |r_z - r_h| is the smallest r innovation of either representation
      // (r >= 0), and nu_r^2 / S_rr <= nu^T S^-1 nu.
      const double dr = observations[j].line.r - p.h.r;
      const double S_rr = p.HPHt(1, 1) + data.R(1, 1);
      if (dr * dr > exclusion * S_rr) continue;
      const LineInnovation innovation = lineInnovation(observations[j].line, p.h);  // eq. 13
      const double d2 = mahalanobisSq(innovation.nu, p.HPHt + data.R);          // eqs. 13–14
      if (!(d2 < exclusion) || !extentsOverlap(i, data)) continue;
      data.in_exclusion_gate = true;  // also for a line already taken: then it is a duplicate piece
      if (!line_taken_[i]) candidates_.push_back({d2, uint32_t(j), uint32_t(i)});
    }
  }
}

void StochasticMap::assignGreedily(UpdateReport* report) {
  // Global nearest neighbour: the closest pairs first, each line and observation at most once.
  std::sort(candidates_.begin(), candidates_.end(),
            [](const Candidate& a, const Candidate& b) { return a.d2 < b.d2; });
  for (const Candidate& c : candidates_) {
    if (line_taken_[c.line] || report->outcomes[c.observation] == ObservationOutcome::kMatched) continue;
    line_taken_[c.line] = 1;
    report->outcomes[c.observation] = ObservationOutcome::kMatched;
    report->matches.push_back({c.observation, c.line, c.d2});
  }
}

bool StochasticMap::selectJointlyCompatible(const std::vector<LineSegment>& observations, size_t first,
                                            UpdateReport* report) {
  // The individual gate (eq. 13) tests each pair alone, but the robot's pose error is common to
  // all of them: after a 2.5 sigma odometry error every innovation is ~2.5 sigma off and the
  // individual gates reject the whole scan together. The stacked innovation's S carries those
  // correlations, so a set whose joint NIS is below chi^2_2k(gate_probability) is accepted
  // whole, even with pairs outside their individual gate (but inside the exclusion gate);
  // otherwise only the individually gated pairs are kept.
  std::vector<LineMatch>& matches = report->matches;
  if (matches.size() <= first) return false;
  const double gate = laser_features::chiSquareQuantile(params_.gate_probability, 2);
  const bool all_individually_gated = std::all_of(matches.begin() + std::ptrdiff_t(first), matches.end(),
                                                  [gate](const LineMatch& m) { return m.nis < gate; });
  const bool stacked = stackInnovations(observations, first, *report);
  if (all_individually_gated) return stacked;
  const size_t k = matches.size() - first;
  if (stacked && batch_nis_ < laser_features::chiSquareQuantile(params_.gate_probability, int(2 * k))) return true;

  size_t kept = first;
  for (size_t a = first; a < matches.size(); ++a) {
    if (matches[a].nis < gate) {
      matches[kept++] = matches[a];
    } else {
      report->outcomes[matches[a].observation] = ObservationOutcome::kAmbiguous;
      line_taken_[matches[a].line] = 0;
    }
  }
  matches.resize(kept);
  return kept > first && stackInnovations(observations, first, *report);
}

bool StochasticMap::stackInnovations(const std::vector<LineSegment>& observations, size_t first,
                                     const UpdateReport& report) {
  const size_t k = report.matches.size() - first;
  ensureMatchCapacity(k);
  const Eigen::Index n = Eigen::Index(stateSize());
  const Eigen::Matrix3d P_rr = robotCovariance();
  const UpdateKernels& kernels = activeUpdateKernels();
  match_jacobians_.resize(k);

  // W = P H^T, one 2-column block per match; H has a robot block and one line block (eq. 15), so
  // each block is O(n): the robot columns of P and the line's two columns.
  for (size_t a = 0; a < k; ++a) {
    const LineMatch& match = report.matches[first + a];
    const LinePrediction& p = predictions_[match.line];
    const LineInnovation innovation = lineInnovation(observations[match.observation].line, p.h);  // eq. 13
    MatchJacobian& J = match_jacobians_[a];
    J.H_robot = innovation.jacobianSign() * p.H_robot;
    J.H_line = innovation.jacobianSign() * p.H_line;
    J.line_index = Eigen::Index(lineIndex(match.line));
    J.R = observation_data_[match.observation].R;
    nu_.segment<2>(Eigen::Index(2 * a)) = innovation.nu;

    const Eigen::Index l = J.line_index;
    const double hr[6] = {J.H_robot(0, 0), J.H_robot(0, 1), J.H_robot(0, 2),
                          J.H_robot(1, 0), J.H_robot(1, 1), J.H_robot(1, 2)};
    const double hl[4] = {J.H_line(0, 0), J.H_line(0, 1), J.H_line(1, 0), J.H_line(1, 1)};
    auto W = W_.block(0, Eigen::Index(2 * a), n, 2);
    kernels.gain_columns(P_.data(), P_.rows(), n, l, hr, hl, W.col(0).data(), W.col(1).data());  // rows 3.. but l, l+1
    const Eigen::Matrix<double, 2, 3> P_lr = P_.block<2, 3>(l, 0);
    W.topRows<3>().noalias() = P_rr * J.H_robot.transpose() + P_lr.transpose() * J.H_line.transpose();
    W.middleRows<2>(l).noalias() = P_lr * J.H_robot.transpose() + lineBlock(match.line) * J.H_line.transpose();
  }
  // S = H W + R (eq. 14), lower block triangle.
  for (size_t a = 0; a < k; ++a) {
    const MatchJacobian& J = match_jacobians_[a];
    for (size_t b = 0; b <= a; ++b) {
      const auto W = W_.block(0, Eigen::Index(2 * b), n, 2);
      S_.block<2, 2>(Eigen::Index(2 * a), Eigen::Index(2 * b)).noalias() =
          J.H_robot * W.topRows<3>() + J.H_line * W.middleRows<2>(J.line_index);
    }
    S_.block<2, 2>(Eigen::Index(2 * a), Eigen::Index(2 * a)) += J.R;
  }
  // S = L L^T in place (Cholesky on the lower triangle; 2k x 2k is small, a plain loop beats a
  // library call), then L^-1 nu by forward substitution.
  const Eigen::Index m = Eigen::Index(2 * k);
  for (Eigen::Index j = 0; j < m; ++j) {
    double d = S_(j, j);
    for (Eigen::Index t = 0; t < j; ++t) d -= S_(j, t) * S_(j, t);
    if (!(d > 0.0)) return false;  // S not positive definite (or not finite)
    const double l_jj = std::sqrt(d);
    S_(j, j) = l_jj;
    inv_diag_(j) = 1.0 / l_jj;
    for (Eigen::Index i = j + 1; i < m; ++i) {
      double v = S_(i, j);
      for (Eigen::Index t = 0; t < j; ++t) v -= S_(i, t) * S_(j, t);
      S_(i, j) = v / l_jj;
    }
    double v = nu_(j);
    for (Eigen::Index t = 0; t < j; ++t) v -= S_(j, t) * nu_(t);
    nu_(j) = v / l_jj;  // L^-1 nu
  }
  batch_nis_ = nu_.head(m).squaredNorm();
  batch_size_ = k;
  return true;
}

void StochasticMap::applyStackedUpdate() {
  const Eigen::Index n = Eigen::Index(stateSize());
  const Eigen::Index m = Eigen::Index(2 * batch_size_);
  const UpdateKernels& kernels = activeUpdateKernels();
  // The kernels' last row block runs into the rows below n: keep them zero (an earlier, larger
  // state or an earlier solve may have left values there that would grow with every update).
  W_.block(n, 0, kUpdateKernelRowPadding, m).setZero();
  // V = W L^-T in place, so K = V L^-1 (eq. 15); eq. 16: x + K nu = x + V (L^-1 nu).
  kernels.solve_and_shift(W_.data(), W_.rows(), S_.data(), S_.rows(), inv_diag_.data(), nu_.data(), x_.data(), n, m);
  // eq. 17: P - K S K^T = P - V V^T, on the lower triangle (symmetric by construction, and the
  // subtracted term is PSD through the Cholesky factor).
  kernels.rank_update_lower(P_.data(), P_.rows(), W_.data(), W_.rows(), n, m);
  x_(2) = normalizeAngle(x_(2));
  for (size_t i = 0; i < numLines(); ++i) canonicalizeLine(i);
}

void StochasticMap::summarizeMatches(UpdateReport* report) const {
  double nis_sum = 0.0;
  for (const LineMatch& match : report->matches) nis_sum += match.nis;
  report->matched = uint32_t(report->matches.size());
  report->mean_nis = report->matched > 0 ? nis_sum / report->matched : 0.0;
}

void StochasticMap::canonicalizeLine(size_t i) {
  const Eigen::Index l = Eigen::Index(lineIndex(i));
  if (x_(l + 1) < 0.0) {
    // (alpha, r) -> (alpha + pi, -r): negate r's row and column (its variance is unchanged).
    x_(l) += kPi;
    x_(l + 1) = -x_(l + 1);
    const Eigen::Index n = Eigen::Index(stateSize());
    P_.block(l + 1, 0, 1, l + 1) *= -1.0;
    P_.block(l + 2, l + 1, n - l - 2, 1) *= -1.0;
  }
  x_(l) = normalizeAngle(x_(l));
}

void StochasticMap::growExtents(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
                                const UpdateReport& report, size_t first) {
  const Pose2D sensor_pose = compose(robotPose(), sensor_in_robot);  // posterior
  for (size_t a = first; a < report.matches.size(); ++a) {
    const LineMatch& match = report.matches[a];
    const Line map_line = line(match.line).line;
    const Eigen::Vector2d direction = map_line.direction();
    const Eigen::Vector2d points[4] = {
        extents_[match.line].start, extents_[match.line].end,
        laser_features::transformPoint(sensor_pose, observations[match.observation].start),
        laser_features::transformPoint(sensor_pose, observations[match.observation].end)};
    size_t lowest = 0, highest = 0;
    for (size_t q = 1; q < 4; ++q) {
      if (direction.dot(points[q]) < direction.dot(points[lowest])) lowest = q;
      if (direction.dot(points[q]) > direction.dot(points[highest])) highest = q;
    }
    extents_[match.line].start = laser_features::projectOntoLine(map_line, points[lowest]);
    extents_[match.line].end = laser_features::projectOntoLine(map_line, points[highest]);
  }
}

// Eqs. 9–11: a new line with its cross-covariances, from the current (posterior) robot pose.
void StochasticMap::addLine(const LineSegment& observation, const Eigen::Matrix2d& R,
                            const Pose2D& sensor_in_robot) {
  Eigen::Matrix2d J_z;
  Matrix23d J_r;
  const Pose2D robot = robotPose();
  const Line in_place = lineFromSensorToPlace(observation.line, robot, sensor_in_robot, &J_z, &J_r);  // eq. 9
  const Eigen::Matrix3d P_rr = robotCovariance();
  ensureLineCapacity(numLines() + 1);
  const Eigen::Index l = Eigen::Index(stateSize());  // the new line's index
  x_(l) = in_place.alpha;
  x_(l + 1) = in_place.r;
  const Eigen::Matrix2d P_new = J_r * P_rr * J_r.transpose() + J_z * R * J_z.transpose();
  P_.block<2, 2>(l, l) = symmetric<2>(P_new);                                                   // eq. 10
  P_.block<2, 3>(l, 0) = J_r * P_rr;                                                            // eq. 11
  if (l > 3) P_.block(l, 3, 2, l - 3).noalias() = J_r * P_.block(3, 0, l - 3, 3).transpose();  // eq. 11

  const Pose2D sensor_pose = compose(robot, sensor_in_robot);
  extents_.push_back(
      {laser_features::projectOntoLine(in_place, laser_features::transformPoint(sensor_pose, observation.start)),
       laser_features::projectOntoLine(in_place, laser_features::transformPoint(sensor_pose, observation.end))});
}

void StochasticMap::addNewLines(const std::vector<LineSegment>& observations,
                                const Pose2D& sensor_in_robot, UpdateReport* report) {
  for (size_t j = 0; j < observations.size(); ++j) {
    if (report->outcomes[j] != ObservationOutcome::kOutOfGate) continue;
    const LineSegment& observation = observations[j];
    if (observation.num_points < params_.new_line_min_points ||
        !(observation.length() >= params_.new_line_min_length)) {
      continue;
    }
    addLine(observation, observation_data_[j].R, sensor_in_robot);
    report->outcomes[j] = ObservationOutcome::kNewLine;
    ++report->new_lines;
  }
}

bool StochasticMap::associate(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
                              UpdateReport* report) {
  const SensorPose sensor = sensorPose(robotPose(), sensor_in_robot);
  placeSegments(observations, sensor.pose);
  predictLines(sensor);
  const size_t first = report->matches.size();
  findCandidates(observations, *report);
  assignGreedily(report);
  // Observations left in some line's exclusion gate are ambiguous (until a later pass takes them).
  for (size_t j = 0; j < observations.size(); ++j) {
    if (observation_data_[j].valid && report->outcomes[j] != ObservationOutcome::kMatched) {
      report->outcomes[j] = observation_data_[j].in_exclusion_gate ? ObservationOutcome::kAmbiguous
                                                                   : ObservationOutcome::kOutOfGate;
    }
  }
  return selectJointlyCompatible(observations, first, report);
}

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
