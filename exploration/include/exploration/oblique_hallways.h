// Hallways leaving a hallway's end at an angle to the building's axes: the wings of a building at
// 30-60 degrees, told from a door seen at a slant by walls running along the way.
//
// ROS-free: Eigen and laser_features only.
#pragma once

#include "exploration/hallway_view.h"
#include "laser_features/line_extractor.h"

#include <Eigen/Core>

#include <vector>

namespace exploration {

/// The ways out of a hallway's end that run at an angle to the building's axes: directions (rad,
/// robot frame) within `max_turn` of `direction` and at least `off_axis` (rad) from every quarter
/// turn of it, along which a corridor of half-width `half_width` (m) from `origin` (robot frame) is
/// free for `min_free` (m). Adjacent free directions (every `step` rad) form one way, reported by
/// its middle direction; left (counter-clockwise) first.
std::vector<double> obliqueWays(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin,
                                double direction, double half_width, double min_free, double max_turn,
                                double off_axis, double step);

/// A hallway at an angle to the axes leaving a hallway's end: its walls' direction (rad, robot
/// frame) and the point (robot frame) from which its way was found free.
struct ObliqueWay {
  double direction = 0.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
};

/// The hallways leaving the end of the hallway seen in `view` (along `direction`, robot frame) at an
/// angle to the axes: wings of the building at 30-60 degrees. A way out (obliqueWays, up to three
/// eighths of a turn to either side, the robot's corridor (params.clearance) free for `min_free`)
/// from the expected crossing's centre or a point across the crossing that the robot fits in (its
/// mouth may be beside the hallway's end), that is a hallway, not a door seen at a slant: seen from
/// a point inside it, walls on both sides run along it within `max_width` of each other, or one
/// wall runs along it and the scan's points across lie within `max_width` of it (the wall on the
/// inner side of the turn is seen edge-on from the hallway's end). Left first; none where there is
/// none.
std::vector<ObliqueWay> obliqueHallways(const std::vector<Eigen::Vector2d>& points,
                                        const std::vector<laser_features::LineSegment>& lines, const HallwayView& view,
                                        double direction, const HallwayViewParams& params, double min_free,
                                        double max_width);

}  // namespace exploration
