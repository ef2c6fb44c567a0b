// StochasticMap, the state changed by a scan: the stacked matches fused (eqs. 15–17), the
// matched lines' extents grown, and the new lines added (eqs. 9–11). The class: stochastic_map.h.
#include "ekf_local_map/stochastic_map.h"
#include "symmetric.h"

#include <cmath>

namespace ekf_local_map {

using laser_features::compose;
using laser_features::kPi;
using laser_features::normalizeAngle;

// ---------------------------------------------------------------------------------------------
// Eqs. 13–17: the stacked update

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

}  // namespace ekf_local_map
