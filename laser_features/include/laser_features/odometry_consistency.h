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
};

class OdometryConsistency {
 public:
  explicit OdometryConsistency(const OdometryConsistencyParams& params = OdometryConsistencyParams());

  /// The fraction in [0, 1] of the previous scan's points that agree with `scan`, given where the
  /// previous scan's frame is in this scan's frame according to odometry; -1 when there is no
  /// previous scan or too few points to compare. Remembers `scan` for the next call.
  double update(const ScanPoints& scan, const Pose2D& previous_in_current);
  /// Forgets the previous scan (e.g. when the odometry for this scan is unknown).
  void reset() {
    previous_.clear();
    across_.clear();
  }

 private:
  enum class Verdict { kNotCompared, kAgrees, kDisagrees };
  Verdict compare(const ScanPoints& scan, const Eigen::Vector2d& q) const;
  void remember(const ScanPoints& scan);

  OdometryConsistencyParams params_;
  std::vector<Eigen::Vector2d> previous_;  // the previous scan's valid points within max_range ...
  std::vector<double> normals_;            // ... their surface normals (rad; NaN: a lone point) ...
  std::vector<uint8_t> across_;            // ... and whether each one's normal is across the dominant one
};

}  // namespace laser_features
