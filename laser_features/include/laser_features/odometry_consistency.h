// Does the odometry explain how the scan changed? The previous scan's points, moved by the odometry
// increment between the two scans, should fall on the new scan's surfaces. When many do not, the
// robot was moved without its wheels knowing (kidnapping, a lift, a teleport in the simulator) or
// the odometry jumped: the topological localizer then resets its belief instead of mapping on.
//
// A point counts when it is within max_range (far points at grazing angles say little) and its
// bearing in the new scan lies inside the new scan's field of view; it agrees when it lies within
// tolerance + tolerance_per_m x range of the new scan's polyline around that bearing (two beams
// each side; only segments between neighbouring points closer than max_gap, so that a point is
// never "explained" by the jump across an occlusion edge). A point whose new beam says nothing
// (invalid reading) is not compared; a "no return" where a point should be disagrees.
//
// In a hallway most points lie on the two side walls, which a move along the hallway does not
// change: counted together, a teleport of metres still agrees at 85-90 %. So the points are split
// by their surface normal into those along the scene's dominant wall direction (the side walls) and
// those across it (hallway ends, door jambs, furniture), and the verdict is the smaller of the two
// fractions (the across class only when it has min_points / 2 points).
#pragma once

#include "laser_features/geometry.h"
#include "laser_features/scan.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace laser_features {

struct OdometryConsistencyParams {
  double max_range = 8.0;          // m, previous points farther than this are not compared
  double tolerance = 0.15;         // m, distance to the new scan's surface that still agrees ...
  double tolerance_per_m = 0.02;   // m/m, ... plus this per metre of range
  double max_gap = 0.5;            // m, neighbouring new points farther apart are not one surface
  int min_points = 50;             // -, fewer compared points: no verdict
  // Search for the best small correction of the odometry increment (3 x 3 x 3 grid, then a grid a
  // third the size around the best) unless the increment itself already agrees this well:
  double good_enough = 0.9;        // -, no search above this
  double search_xy = 0.1;          // m, grid step in x and y ...
  double search_xy_per_m = 0.1;    // m/m, ... plus this per metre of the increment
  double search_theta = 0.035;     // rad (2 deg), grid step in heading ...
  double search_theta_per_rad = 0.1;  // rad/rad, ... plus this per radian of the increment
  double recheck_below = 0.75;     // -, a pair below this is confirmed against the next scan first
};

class OdometryConsistency {
 public:
  explicit OdometryConsistency(const OdometryConsistencyParams& params = OdometryConsistencyParams());

  /// `scan` taken with the sensor at `sensor_in_odom` (odometry frame). Returns the fraction in
  /// [0, 1] of the previous scan's points that agree with it, given the odometry increment (or a
  /// small correction of it, see the search parameters); -1 when there is no previous scan or too
  /// few points to compare. A pair below recheck_below is not reported at once (-1): the next scan
  /// is compared with the scan before the doubtful one, and that value is reported. So a single
  /// odd scan (a glitch, a person in front of the sensor) does not look like a jump, while after
  /// a real jump every later scan disagrees with the scans from before it.
  double update(const ScanPoints& scan, const Pose2D& sensor_in_odom);
  /// Forgets the scans seen so far (e.g. when the odometry for this scan is unknown).
  void reset() {
    previous_.valid = false;
    reference_.valid = false;
  }

 private:
  /// A remembered scan: its valid points within max_range, whether each point's surface normal is
  /// across the scene's dominant wall direction, and where the sensor was.
  struct Keyframe {
    std::vector<Eigen::Vector2d> points;
    std::vector<uint8_t> across;
    std::vector<double> normals;  // rad; NaN: a lone point (scratch of remember())
    Pose2D pose;
    bool valid = false;
  };
  enum class Verdict { kNotCompared, kAgrees, kDisagrees };
  Verdict compare(const ScanPoints& scan, const Eigen::Vector2d& q) const;
  void remember(const ScanPoints& scan, const Pose2D& pose, Keyframe* frame);
  double score(const Keyframe& frame, const ScanPoints& scan, const Pose2D& frame_in_current) const;
  /// score() at the odometry increment, or the best of the correction grid around it.
  double bestScore(const Keyframe& frame, const ScanPoints& scan, const Pose2D& sensor_in_odom) const;

  OdometryConsistencyParams params_;
  Keyframe previous_;
  Keyframe reference_;  // the scan before a doubtful pair, while the next scan is awaited
};

}  // namespace laser_features
