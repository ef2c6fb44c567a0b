// What the current scan says about the hallway around the robot, along a travel direction: the free
// distance ahead, whether the sides are open (a branch or a crossing hallway, not a door), the
// hallway's walls parallel to the direction (their lateral offsets and their direction), and so the
// mid-line to follow (Tomatis et al. 2001, section 3.1: "the robot follows the hallway's centre").
//
// ROS-free: Eigen and laser_features only.
#pragma once

#include "laser_features/building_rules.h"
#include "laser_features/building_axes.h"
#include "laser_features/line_extractor.h"
#include "laser_features/opening_extractor.h"

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace exploration {

struct HallwayViewParams {
  double ahead_sector = 0.17;          // rad (10 deg), half-width of the sector of the free distance ahead
  double side_open_distance = 2.0;     // m, the robot's corridor into a side is free this far at an open way
                                       // (a branch's mouth, an open area's side)
  // rad (15 deg), lines this close to the direction are walls; m, shorter lines are no hallway walls
  // (the defaults are laser_features::HallwayWallsParams', whose rule finds a wing's walls)
  double wall_parallel_tolerance = laser_features::HallwayWallsParams().parallel_tolerance;
  double wall_min_length = laser_features::HallwayWallsParams().min_length;
  // m, a wall beside the robot reaches from this far behind it to this far ahead, and lies at least
  // this far to a side (nearer lines are the robot's own clutter): laser_features' window, not configured
  double wall_behind = laser_features::HallwayWallsParams().behind;
  double wall_ahead = laser_features::HallwayWallsParams().ahead;
  double wall_min_lateral = laser_features::HallwayWallsParams().min_lateral;
  double min_wall_clearance = 0.8;     // m, with one wall only the mid-line keeps at least this far from
                                       // it; along an open area's wall exactly this far
  double wall_same_lateral = 0.3;      // m, lines this close to a wall's lateral offset are that wall
                                       // (its pieces between doors; a wall is 0.1-0.2 m thick)
  // Derived, not configured (HallwayFollower sets them from config/robot.yaml and config/building.yaml):
  double clearance = 0.35;             // m, the robot's radius and safety margin
  double min_mouth = 1.4;              // m, the narrowest hallway's mouth: hallway_min_width - width_tolerance
  double widest_hallway = 4.3;         // m, hallway_max_width + width_tolerance
  double wall_max_lateral = 2.0;       // m, walls farther to the side are not this hallway's:
                                       // BuildingRules::hallwayReach, half hallway_max_width
};

struct HallwayView {
  double free_ahead = 0.0;       // m, nearest scan point in the ahead sector (range cap if none)
  bool open_left = false;        // from the robot: the side sector is free, or a hallway's mouth is beside it
  bool open_right = false;
  // At a hallway's end: the sides seen from where the crossing's centre is expected (free_ahead
  // less half this hallway's width ahead) or, for a narrower side hallway, from between there and
  // the end wall: an L or T corner opens there, not beside the robot.
  bool end_open_left = false;
  bool end_open_right = false;
  // Where a crossing's centre is expected (robot frame): half this hallway's width short of the
  // free distance ahead, on the mid-line.
  Eigen::Vector2d end_centre = Eigen::Vector2d::Zero();
  // Where each side's mouth was seen from (robot frame, on the mid-line between end_centre and the
  // end wall; end_centre where the side is closed): a door in the mouth is looked for there.
  Eigen::Vector2d end_mouth_left = Eigen::Vector2d::Zero(), end_mouth_right = Eigen::Vector2d::Zero();
  bool left_wall = false, right_wall = false;
  double left_lateral = 0.0;     // m, lateral offset of the nearest left wall (> 0), robot frame along the direction
  double right_lateral = 0.0;    // m, (< 0)
  double wall_direction = 0.0;   // rad, robot frame: the walls' direction (the travel direction refined)
  bool wall_direction_valid = false;
  double centre_offset = 0.0;    // m, lateral offset of the mid-line from the robot (+ left)
  // One wall seen (or, none within wall_max_lateral, the nearest within the widest hallway), and
  // beyond the robot on the other side an open area (free deeper than the widest hallway): the
  // mid-line is min_wall_clearance from that wall.
  bool open_area_beside = false;
  // m, how far ahead along the direction the walls at left_lateral and right_lateral (every line
  // within wall_same_lateral of them) reach: a hallway goes on where its walls do.
  double left_reach = -1e9, right_reach = -1e9;
  // A wall crosses the hallway at free_ahead: no lane as wide as the narrowest hallway's mouth is
  // free past it, and the hallway's walls do not run on beside it (a door in it is no way on).
  bool wall_across = false;
  double width() const { return left_wall && right_wall ? left_lateral - right_lateral : 0.0; }
  /// A wall of the hallway reaches farther ahead than `distance` (m).
  bool wallsReach(double distance) const {
    return (left_wall && left_reach > distance) || (right_wall && right_reach > distance);
  }
};

/// A lane along the hallway the robot fits through: its lateral offset (m, robot frame, + left) and
/// how far ahead it is free (m).
struct Lane {
  double lateral = 0.0;
  double free = 0.0;
};

/// The lane between the hallway's walls in `view` (the mid-line where only one wall is seen) whose
/// corridor of half-width `clearance` (m: the robot's radius and margin) is free the farthest along
/// `direction` (rad, robot frame); of equally free lanes, the one nearest the mid-line. Lanes are
/// tried every 0.1 m.
Lane freestLane(const std::vector<Eigen::Vector2d>& points, double direction, const HallwayView& view,
                double clearance, double range_cap = 15.0);

/// The hallway along `direction` (rad, robot frame) seen in the scan `points` (robot frame) and the
/// extracted `lines` (robot frame). `range_cap` (m) is the free distance reported for an empty sector.
HallwayView viewHallway(const std::vector<Eigen::Vector2d>& points,
                        const std::vector<laser_features::LineSegment>& lines, double direction,
                        const HallwayViewParams& params, double range_cap = 15.0);

/// The sides of `v`'s hallway end (free_ahead along `direction`, robot frame), seen from where a
/// crossing's centre is expected there and on to the end wall: end_centre, end_open_left,
/// end_open_right, end_mouth_left, end_mouth_right.
void seeEnd(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
            double direction, const HallwayViewParams& params, HallwayView* v);

/// `v` ends at a wall across its hallway `distance` m ahead along `direction` (robot frame): the free
/// distance ahead, wall_across, and the sides seen from the crossing's expected centre (seeEnd).
void endWallAt(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
               double direction, const HallwayViewParams& params,
               double distance, HallwayView* v);

/// A door as wide as a hallway's mouth (`min_mouth`, m): laser_features' kind door
/// (BuildingRules::isDoor: a double door with a room behind it is a door, though a lane as wide as
/// a mouth passes through it). A narrower door lets no such lane through: a lane or mouth found
/// where one is lies beside it.
bool mouthWideDoor(const laser_features::Opening& o, double min_mouth);

/// A door across the hallway of `v` ahead (m, along `direction`, robot frame), nearer than its free
/// distance: one of laser_features' `openings` that is a mouthWideDoor (params.min_mouth), facing
/// along the direction (within the walls' tolerance), spanning the mid-line, and narrower than the
/// hallway by its jambs where both walls are seen (BuildingRules::fitsInEndWall: one as wide is the
/// hallway's own mouth). A hallway does not go on through a door: its wall crosses the hallway there.
std::optional<double> doorAcross(const std::vector<laser_features::Opening>& openings, const HallwayView& v,
                                 double direction, const HallwayViewParams& params,
                                 const laser_features::BuildingRules& rules);

/// viewHallway as seen from `origin` (robot frame) instead of the robot; distances and offsets are
/// from `origin`.
HallwayView viewHallwayFrom(const std::vector<Eigen::Vector2d>& points,
                            const std::vector<laser_features::LineSegment>& lines, const Eigen::Vector2d& origin,
                            double direction, const HallwayViewParams& params, double range_cap = 15.0);

/// rad, how far `heading` is from the nearest quarter turn of `axis` (both robot frame).
double offAxis(double heading, double axis);

/// A line's difference in direction (rad, robot frame) to a hallway's and its lateral offset (m, + left).
struct WallBeside {
  double diff, lateral;
};
/// A wall of the hallway along `direction` (unit `u`, left normal `n`): a line at least
/// wall_min_length long, parallel to the direction within wall_parallel_tolerance (modulo pi: a wall
/// has no orientation), running beside the robot (not only far ahead or behind), between wall_min_lateral and
/// `max_lateral` to a side. Its direction difference (rad, robot frame) and lateral offset (m, + left).
std::optional<WallBeside> wallBeside(const laser_features::LineSegment& l, double direction, const Eigen::Vector2d& u,
                                     const Eigen::Vector2d& n, const HallwayViewParams& params, double max_lateral);

/// How far a corridor of half-width `half_width` (m) from `origin` along `bearing` (robot frame) is
/// free of scan points (m, `range_cap` if no point is in it).
double corridorFree(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double bearing,
                    double half_width, double range_cap);

/// A wall of `view`'s hallway (lines along `direction`, robot frame, at its left or right wall's
/// lateral offset) runs on from `from` to `to` m ahead, broken by single doors only: gaps between
/// its lines narrower than the narrowest hallway's mouth (params.min_mouth) with no wall across
/// meeting it there (no scan point of `points` standing out of the wall's line into the hallway,
/// up to params.clearance). A door in the wall beside an obstacle does not end the hallway there;
/// a crossing hallway's mouth, a double door, or an end wall whose corner lines up with a room's
/// wall beyond it does.
bool wallsSpan(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
               const HallwayView& view, double direction, double from, double to, const HallwayViewParams& params);

/// A hallway's mouth beside `origin` (robot frame) on the `side` (+1 left, -1 right) of `direction`:
/// the robot's corridor (half-width `clearance`) straight to that side is free for `depth` (m) from
/// `origin` and from every point along `direction` up to where the mouth's edges stop it, and the
/// mouth (the free stretch and the corridor's width) is at least `min_mouth` (m) wide. A door is
/// narrower: the narrowest hallway (less the width error) is wider than the widest single door. (A
/// sector's free distance is no test: from a narrow hallway's middle a door subtends more than any
/// sector a narrow branch off a wide hallway opens.)
bool mouthBeside(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double direction, int side,
                 double clearance, double min_mouth, double depth);

/// A door where a mouth beside `origin` (robot frame) on the `side` (+1 left, -1 right) of
/// `direction` opens: one of laser_features' `openings` of kind door (BuildingRules::isDoor: a
/// double door as wide as the narrowest hallway's mouth, with a room behind it whose free space
/// reaches past its edges; a hallway's walls run on from its mouth's) on that side, facing that
/// way (normal within `side_angle` of it), whose edges span the robot's corridor straight to the
/// side (half-width `clearance`). Such a mouth is a door, not a branch.
bool doorInMouth(const std::vector<laser_features::Opening>& openings, const Eigen::Vector2d& origin, double direction,
                 int side, double clearance, double min_mouth, double side_angle);

/// Open space beside `origin` (robot frame) on the `side` (+1 left, -1 right) of `direction`, wider
/// along it than the widest hallway's mouth (`widest_hallway`, m): the robot's corridor straight to
/// that side is free for `depth` (m) over more than that stretch. A hallway's mouth is no wider: the
/// side opens onto an open hall or lobby (or the hallways around one), not onto a branch.
bool openAreaBeside(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double direction,
                    int side, double clearance, double widest_hallway, double depth);

/// The nearest scan point's distance within `half_width` (rad) of `bearing` (robot frame).
double freeDistance(const std::vector<Eigen::Vector2d>& points, double bearing, double half_width,
                    double range_cap, const Eigen::Vector2d& origin = Eigen::Vector2d::Zero());

}  // namespace exploration
