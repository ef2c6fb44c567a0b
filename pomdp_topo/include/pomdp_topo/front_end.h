// From scans to the POMDP's abstraction (Tomatis et al. 2001, section 3.3): the heading estimator
// corrects the odometry's heading; the corrected dead reckoning gives Travel actions along the
// current heading bin and Turn actions when the heading moves to another bin; corners and openings
// are tracked over scans in the corrected frame (the "observation graph" of the features around
// the robot), passed landmarks are reported once, and the tracks near the robot make the
// observation, in the travel frame.
#pragma once

#include "laser_features/corner_extractor.h"
#include "laser_features/geometry.h"
#include "laser_features/opening_extractor.h"
#include "laser_features/opening_tracks.h"
#include "pomdp_topo/heading_estimator.h"
#include "pomdp_topo/observation.h"

#include <string>
#include <vector>

namespace pomdp_topo {

struct FrontEndParams {
  double resolution = 0.5;           // m, a Travel action is emitted per this much travel (the POMDP's cell)
  int heading_bins = 4;              // -, discrete headings (4: the building's N, E, S, W)
  double axis_angle = 0.0;           // rad, heading of bin 0 in the map frame (the building's axis)
  double turn_hysteresis = 0.26;     // rad (15 deg), past the half-bin boundary before a turn starts
  double turn_settle_angle = 0.3;    // rad, a turn is emitted once the heading is this close to a bin's
                                     // heading and the rotation has slowed below track_max_rotation
  double max_feature_range = 5.0;    // m, features farther from the robot are not tracked
  double track_gate = 0.5;           // m, a feature this close to a track of its type updates the track
  double min_confidence = 0.3;       // -, mean extraction confidence a track needs
  double observation_range = 3.5;    // m, tracks within this along and lateral distance are observed
  double track_max_rotation = 0.05;  // rad, scans during which the robot turned more are not tracked
                                     // (the heading estimate lags in fast turns)
  double max_odometry_step = 3.0;    // m, a larger odometry jump between scans is refused (a reset), not travelled
  laser_features::BuildingRules rules;  // which tracked openings are doors (config/building.yaml)
  laser_features::OpeningTracks tracks;  // side openings, sightings, keep distance (config/opening_tracks.yaml)
};

/// A landmark the robot has just passed (abeam and tracks.pass_lag behind), in the travel frame at
/// that moment.
struct PassedLandmark {
  ObservedLandmark landmark;
  double travel = 0.0;      // m, total signed travel (along headings) when it was passed
  int heading_bin = 0;      // travel heading bin then
  double skew = 0.0;        // rad, the travel heading's angle to that bin then (FrontEnd::wingOffset)
  uint32_t track_id = 0;
};

class FrontEnd {
 public:
  explicit FrontEnd(const FrontEndParams& params = FrontEndParams(),
                    const HeadingEstimatorParams& heading_params = HeadingEstimatorParams());
  const FrontEndParams& params() const { return params_; }

  /// Starts over at `odom` with the heading estimate `theta` (map frame) and its variance. The
  /// position starts at odom's: the map frame is the odometry frame at the first scan.
  void reset(const Pose2D& odom, double theta, double variance);

  /// One scan: `odom` is the robot's odometry pose at the scan's stamp; lines, corners and
  /// openings are in the robot frame. Appends the actions it caused to `actions`. Returns false
  /// with `error` set (and changes nothing) for a non-finite pose or an odometry jump.
  bool process(const Pose2D& odom, const std::vector<laser_features::LineSegment>& lines,
               const std::vector<laser_features::Corner>& corners,
               const std::vector<laser_features::Opening>& openings, std::vector<Action>* actions,
               std::string* error = nullptr);

  /// The confirmed tracks within observation_range, in the travel frame, with the heading.
  Observation observation() const;
  /// Landmarks passed since the last call.
  std::vector<PassedLandmark> takePassed();

  /// Corrected dead-reckoning pose (map-aligned: heading from the estimator).
  Pose2D pose() const { return pose_; }
  int headingBin() const { return bin_; }
  /// The discrete headings along the building's axes (the one conversion, laser_features).
  laser_features::HeadingBins headingBins() const { return {params_.axis_angle, params_.heading_bins}; }
  double binHeading(int bin) const { return headingBins().heading(bin); }
  /// The heading travel is measured along and the travel frame's: the bin's, turned by the wing's
  /// offset where the robot follows a hallway at an angle to the axes.
  double travelHeading() const { return laser_features::normalizeAngle(binHeading(bin_) + wing_offset_); }
  /// rad, the offset from the bin's heading of the hallway the robot follows (0 along the axes).
  double wingOffset() const { return wing_offset_; }
  /// The building's axis (rad, map frame), once it is known (before the first scan is processed:
  /// the heading bins of everything mapped are along it).
  void setAxis(double axis_angle) {
    params_.axis_angle = axis_angle;
    heading_.setAxis(axis_angle);
  }
  /// Total signed travel along the travel headings, m.
  double travel() const { return travel_; }
  /// Travel not yet emitted as an action (below one resolution step), m.
  double pendingTravel() const { return pending_; }
  const HeadingEstimator& heading() const { return heading_; }
  /// Sets the travel heading bin and the travel not yet emitted without a Turn action (after a pause
  /// of the topological map: the robot is back where and how it left the hallway, whatever it
  /// turned and travelled meanwhile; `pending` is pendingTravel() from when it left).
  void setHeadingBin(int bin, double pending = 0.0, double wing_offset = 0.0);
  /// Re-aligns the heading by whole bins (after a kidnapping, when the topological belief says so).
  void shiftHeading(int bins);
  /// Forgets every tracked feature and unreported passed landmark (after an odometry jump: their
  /// positions in the odometry frame no longer say where they are).
  void clearTracks() {
    tracks_.clear();
    passed_.clear();
  }
  /// Moves the corrected pose to `position` (m, map frame), keeping the heading: after an odometry
  /// jump, once the belief says where the robot is again, so that new nodes and loop candidates are
  /// placed where the map has them rather than 'where odometry thinks'. Tracks are forgotten.
  void setPosition(const Eigen::Vector2d& position) {
    pose_.x = position.x();
    pose_.y = position.y();
    clearTracks();
  }
  bool initialized() const { return initialized_; }

  struct Track {
    uint32_t id = 0;
    LandmarkType type = LandmarkType::Corner;
    Eigen::Vector2d position = Eigen::Vector2d::Zero();  // corrected frame
    double orientation = 0.0;                            // rad, corrected (map) frame
    double width = 0.0;
    double confidence_sum = 0.0;
    int sightings = 0;
    int room_sightings = 0;  // openings: scans that saw a room behind it
    bool armed = false;  // seen ahead of the robot since it was last passed
    double confidence() const { return sightings > 0 ? confidence_sum / sightings : 0.0; }
  };
  const std::vector<Track>& tracks() const { return tracks_; }

 private:
  void track(LandmarkType type, const Eigen::Vector2d& p_robot, double theta_robot, double width,
             double confidence, bool room_behind = false);
  bool confirmed(const Track& t) const;
  ObservedLandmark toTravelFrame(const Track& t) const;
  void checkPassed();
  /// The hallway's walls around the robot set the travel heading: a wing's offset from the bin, or
  /// none along the axes; a Turn where they put the robot in another bin (appended to `actions`).
  void followWalls(const std::vector<laser_features::LineSegment>& lines, double rotation, std::vector<Action>* actions);

  FrontEndParams params_;
  HeadingEstimator heading_;
  bool initialized_ = false;
  Pose2D last_odom_;
  Pose2D pose_;
  int bin_ = 0;
  double wing_offset_ = 0.0;  // rad, travelHeading()'s offset from the bin's heading
  double travel_ = 0.0;
  double pending_ = 0.0;
  bool turning_ = false;
  uint32_t next_track_id_ = 0;
  std::vector<Track> tracks_;
  std::vector<PassedLandmark> passed_;
};

}  // namespace pomdp_topo
