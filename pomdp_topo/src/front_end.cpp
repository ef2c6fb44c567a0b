#include "pomdp_topo/front_end.h"

#include <algorithm>
#include <cmath>

namespace pomdp_topo {

using laser_features::kPi;
using laser_features::normalizeAngle;

FrontEnd::FrontEnd(const FrontEndParams& params, const HeadingEstimatorParams& heading_params)
    : params_(params), heading_(heading_params) {}

void FrontEnd::reset(const Pose2D& odom, double theta, double variance) {
  heading_.reset(theta, variance);
  last_odom_ = odom;
  // The map frame is the odometry frame at the first scan, whenever that scan comes: a robot that
  // drove off before pomdp_topo started maps where it is, not at the origin.
  pose_ = Pose2D{odom.x, odom.y, heading_.theta()};
  bin_ = headingBins().bin(theta);
  wing_offset_ = 0.0;
  travel_ = 0.0;
  pending_ = 0.0;
  turning_ = false;
  tracks_.clear();
  passed_.clear();
  initialized_ = true;
}

void FrontEnd::shiftHeading(int bins) {
  heading_.shift(bins * 4 / params_.heading_bins);  // the estimator shifts by quarter turns
  pose_.theta = heading_.theta();
  bin_ = headingBins().wrap(bin_ + bins);
  wing_offset_ = 0.0;
  // Tracks are kept in the corrected frame, which has just rotated: they no longer line up.
  tracks_.clear();
}

void FrontEnd::setHeadingBin(int bin, double pending, double wing_offset) {
  bin_ = headingBins().wrap(bin);
  wing_offset_ = std::isfinite(wing_offset) ? wing_offset : 0.0;
  turning_ = false;
  pending_ = std::isfinite(pending) ? pending : 0.0;
}

bool FrontEnd::process(const Pose2D& odom, const std::vector<laser_features::LineSegment>& lines,
                       const std::vector<laser_features::Corner>& corners,
                       const std::vector<laser_features::Opening>& openings, std::vector<Action>* actions,
                       std::string* error) {
  if (!std::isfinite(odom.x) || !std::isfinite(odom.y) || !std::isfinite(odom.theta)) {
    if (error) *error = "non-finite odometry pose";
    return false;
  }
  if (!initialized_) reset(odom, odom.theta, 1e-4);
  // Odometry increment in the robot frame of the previous scan.
  const Pose2D delta = laser_features::compose(laser_features::inverse(last_odom_), odom);
  const double step = std::hypot(delta.x, delta.y);
  if (step > params_.max_odometry_step) {
    if (error) *error = "odometry jump of " + std::to_string(step) + " m between two scans (more than max_odometry_step)";
    last_odom_ = odom;  // start over from here: the jump itself is not travelled
    return false;
  }
  last_odom_ = odom;

  // Heading: odometry prediction, then lines parallel or perpendicular to the building's axes.
  heading_.predict(delta.theta, step);
  std::vector<HeadingEstimator::LineObs> obs;
  obs.reserve(lines.size());
  for (const auto& l : lines) obs.push_back({l.line.alpha, l.line.cov(0, 0), l.length()});
  heading_.update(obs);

  // Corrected dead reckoning: the translation rotated by the estimated heading (mid-point).
  const double theta_mid = normalizeAngle(heading_.theta() - 0.5 * delta.theta);
  pose_.x += std::cos(theta_mid) * delta.x - std::sin(theta_mid) * delta.y;
  pose_.y += std::sin(theta_mid) * delta.x + std::cos(theta_mid) * delta.y;
  pose_.theta = heading_.theta();

  // Travel along the current bin heading.
  const double hb = travelHeading();
  const double along = std::cos(hb) * (std::cos(theta_mid) * delta.x - std::sin(theta_mid) * delta.y) +
                       std::sin(hb) * (std::sin(theta_mid) * delta.x + std::cos(theta_mid) * delta.y);
  pending_ += along;
  travel_ += along;
  if (std::abs(pending_) >= params_.resolution) {
    const double steps = std::trunc(pending_ / params_.resolution);
    actions->push_back({Action::Travel, steps * params_.resolution, 0});
    pending_ -= steps * params_.resolution;
  }

  // Turns: once the heading left the current bin by more than half a bin plus the hysteresis, the
  // turn is under way; it is emitted as one action when the rotation settles near a bin's heading
  // (so that a U-turn on the spot is one Turn of two bins, not two quarter turns).
  const double bin_width = headingBins().width();
  const double off = normalizeAngle(heading_.theta() - hb);
  if (!turning_ && std::abs(off) > 0.5 * bin_width + params_.turn_hysteresis) turning_ = true;
  if (turning_) {
    const int k = int(std::lround(off / bin_width));
    const double residual = std::abs(off - k * bin_width);
    if (std::abs(delta.theta) <= params_.track_max_rotation && residual < params_.turn_settle_angle) {
      turning_ = false;
      if (k != 0) {
        actions->push_back({Action::Turn, 0.0, k});
        bin_ = headingBins().wrap(bin_ + k);
        pending_ = 0.0;  // travel before the turn that did not make a step is dropped
      }
    }
  }
  followWalls(lines, delta.theta, actions);

  // Tracks in the corrected frame (not while turning fast).
  const bool steady = std::abs(delta.theta) <= params_.track_max_rotation;
  for (const auto& c : corners) {
    if (!steady) break;
    track(LandmarkType::Corner, c.position, c.theta, 0.0, c.confidence);
  }
  for (const auto& o : openings) {
    if (!steady) break;
    track(LandmarkType::Opening, o.center, o.theta, o.width, o.confidence, o.room_behind);
  }
  const Eigen::Vector2d robot(pose_.x, pose_.y);
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) { return (t.position - robot).norm() > params_.tracks.keep_distance; }),
                tracks_.end());
  checkPassed();
  return true;
}

void FrontEnd::track(LandmarkType type, const Eigen::Vector2d& p_robot, double theta_robot, double width,
                     double confidence, bool room_behind) {
  if (!p_robot.allFinite() || !std::isfinite(theta_robot) || !std::isfinite(confidence)) return;
  if (p_robot.norm() > params_.max_feature_range) return;
  const Eigen::Vector2d p = laser_features::transformPoint(pose_, p_robot);
  const double theta = normalizeAngle(pose_.theta + theta_robot);
  Track* best = nullptr;
  double best_d = params_.track_gate;
  for (auto& t : tracks_) {
    if (t.type != type) continue;
    // Openings seen from both sides have opposite normals: the same opening.
    const double dth = std::abs(normalizeAngle(t.orientation - theta));
    if (type == LandmarkType::Corner && dth > 0.8) continue;
    const double d = (t.position - p).norm();
    if (d < best_d) {
      best_d = d;
      best = &t;
    }
  }
  if (best == nullptr) {
    Track t;
    t.id = next_track_id_++;
    t.type = type;
    t.position = p;
    t.orientation = theta;
    t.width = width;
    t.confidence_sum = confidence;
    t.sightings = 1;
    t.room_sightings = room_behind ? 1 : 0;
    tracks_.push_back(t);
    return;
  }
  // Running mean of position and width; the orientation follows the latest sighting's side.
  const double n = best->sightings;
  best->position = (best->position * n + p) / (n + 1.0);
  best->width = (best->width * n + width) / (n + 1.0);
  best->orientation = normalizeAngle(best->orientation + normalizeAngle(theta - best->orientation) / (n + 1.0));
  best->confidence_sum += confidence;
  best->sightings += 1;
  if (room_behind) best->room_sightings += 1;
}

bool FrontEnd::confirmed(const Track& t) const {
  return t.sightings >= params_.tracks.min_sightings && t.confidence() >= params_.min_confidence;
}

void FrontEnd::followWalls(const std::vector<laser_features::LineSegment>& lines, double rotation,
                           std::vector<Action>* actions) {
  // A wing's walls run 30-60 deg off the building's axes: travel, turns and the travel frame (its
  // doors are side openings, +-90 deg of it) follow the walls of the hallway the robot drives
  // along (a pair beside it within the walls' parallel tolerance of its heading: the robot keeps
  // to a hallway's mid-line), by the exploration's rule (laser_features::followWalls). Not while
  // turning: the heading lags.
  if (turning_ || std::abs(rotation) > params_.track_max_rotation) return;
  laser_features::HallwayWallsParams walls;
  walls.max_width = params_.rules.widestHallway();
  const std::optional<double> along = laser_features::hallwayWallsDirection(lines, 0.0, walls.parallel_tolerance, walls);
  if (!along) return;
  const laser_features::HeadingBins bins = headingBins();
  const laser_features::BinnedDirection d = laser_features::followWalls(
      bins, {bin_, wing_offset_}, normalizeAngle(heading_.theta() + *along), walls.parallel_tolerance);
  wing_offset_ = d.offset;
  // The wing's direction is a wall family of the heading filter once the heading is known to better
  // than the walls' parallel tolerance (2 sigma): its walls then correct the heading, as the axes' do.
  if (d.offset != 0.0 && 2.0 * std::sqrt(heading_.variance()) <= walls.parallel_tolerance) {
    heading_.addWallFamily(d.offset, walls.parallel_tolerance);
  }
  const int k = int(std::lround(normalizeAngle(bins.heading(d.bin) - bins.heading(bin_)) / bins.width()));
  if (k != 0) {
    actions->push_back({Action::Turn, 0.0, k});
    bin_ = d.bin;
    pending_ = 0.0;
  }
}

ObservedLandmark FrontEnd::toTravelFrame(const Track& t) const {
  const double h = travelHeading();
  const Eigen::Vector2d rel = t.position - Eigen::Vector2d(pose_.x, pose_.y);
  ObservedLandmark o;
  o.type = t.type;
  o.along = std::cos(h) * rel.x() + std::sin(h) * rel.y();
  o.lateral = -std::sin(h) * rel.x() + std::cos(h) * rel.y();
  o.orientation = normalizeAngle(t.orientation - h);
  if (t.type == LandmarkType::Opening && o.lateral * std::sin(o.orientation) < 0.0) {
    // An opening's normal points away from the hallway the robot is in (seen from the other side
    // it flips): orient it away from the travel line.
    o.orientation = normalizeAngle(o.orientation + kPi);
  }
  o.width = t.width;
  o.door = t.type == LandmarkType::Opening && params_.rules.isDoorTracked(t.width, t.room_sightings);
  o.confidence = std::min(1.0, t.confidence());
  return o;
}

Observation FrontEnd::observation() const {
  Observation out;
  out.heading = heading_.theta();
  out.heading_variance = heading_.variance();
  out.heading_valid = initialized_;
  for (const auto& t : tracks_) {
    if (!confirmed(t)) continue;
    const ObservedLandmark o = toTravelFrame(t);
    if (std::abs(o.along) <= params_.observation_range && std::abs(o.lateral) <= params_.observation_range) {
      out.landmarks.push_back(o);
    }
  }
  return out;
}

void FrontEnd::checkPassed() {
  // A track is armed while it is ahead of (or abeam) the robot; it is passed once it is behind,
  // confirmed (its confirmation may come a little after it went behind), and armed.
  for (auto& t : tracks_) {
    const ObservedLandmark o = toTravelFrame(t);
    const bool behind = o.along < -params_.tracks.pass_lag;
    if (!behind) t.armed = true;
    if (t.armed && behind && confirmed(t)) {
      const bool side = t.type == LandmarkType::Corner ||
                        std::abs(std::abs(o.orientation) - 0.5 * kPi) <= params_.tracks.side_angle;
      const double max_lateral = t.type == LandmarkType::Opening ? params_.rules.hallwayReach() : params_.observation_range;
      if (side && std::abs(o.lateral) <= max_lateral) {
        passed_.push_back({o, travel_, bin_, wing_offset_, t.id});
      }
      t.armed = false;
    }
  }
}

std::vector<PassedLandmark> FrontEnd::takePassed() {
  std::vector<PassedLandmark> out;
  out.swap(passed_);
  return out;
}

}  // namespace pomdp_topo
