// StochasticMap, association (eqs. 12–14): which observation is which map line. The observations
// checked and placed, the map lines predicted in the sensor frame, candidates gated, assigned by
// global nearest neighbour and tested for joint compatibility. The class: stochastic_map.h.
#include "ekf_local_map/stochastic_map.h"
#include "symmetric.h"

#include "laser_features/chi_square.h"

#include <algorithm>
#include <cmath>

namespace ekf_local_map {

// ---------------------------------------------------------------------------------------------
// Eqs. 12–14: association

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

void StochasticMap::summarizeMatches(UpdateReport* report) const {
  double nis_sum = 0.0;
  for (const LineMatch& match : report->matches) nis_sum += match.nis;
  report->matched = uint32_t(report->matches.size());
  report->mean_nis = report->matched > 0 ? nis_sum / report->matched : 0.0;
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

}  // namespace ekf_local_map
