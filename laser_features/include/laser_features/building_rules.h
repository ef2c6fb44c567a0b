// Building assumptions that several nodes decide with (DESIGN.md: thresholds come from the robot and
// from stated building ranges, never from one world). One struct, one YAML (config/building.yaml,
// loaded by every launch file into the `building` namespace), one reader: laser_features classifies
// openings with it, pomdp_topo types its nodes with it, the coordinator picks doors to enter with it.
//
// Office, lab and school floors have single doors 0.7-1.2 m and double doors 1.4-1.8 m wide, and
// hallways 1.5-4.0 m wide. So:
//  - an opening narrower than the narrowest hallway (less the width error) is a door by its width;
//  - an opening of a double door's width may be a door or a hallway's mouth: width alone cannot tell
//    a 1.6 m double door from a 1.5 m hallway. Geometry does: a door opens into a room, whose free
//    space reaches past the door's edges behind the wall, while a hallway's walls continue from the
//    edges of its mouth. A hallway leaving at an angle phi to the wall has a mouth of width / sin phi,
//    so one whose mouth is no wider than a door leaves at phi >= asin(hallway_min / door_max) and its
//    walls run from the edges at most cot(phi) per metre beyond them (branchSpread);
//  - wider openings are junctions;
//  - a door in a wall across a hallway leaves 0.2-0.5 m of that wall on each side (its frame): an
//    opening as wide as the hallway is the hallway's mouth (fitsInEndWall).
//
// ROS-free: the standard library only.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

namespace laser_features {

struct BuildingRules {
  double door_min_width = 0.7;     // m, narrowest door (and opening) there is: the narrowest single door
  double door_max_width = 1.8;     // m, widest door: the widest double door
  double hallway_min_width = 1.5;  // m, narrowest hallway
  double hallway_max_width = 4.0;  // m, widest hallway (an open hall or lobby is wider)
  double width_tolerance = 0.1;    // m, a measured opening's width may be this much off the true one
  double door_jamb_min = 0.2;      // m, least wall on each side of a door in a hallway's end wall (its frame)

  /// m, the widest hallway as measured: no hallway's walls are farther apart (an open area's are).
  double widestHallway() const { return hallway_max_width + width_tolerance; }
  /// m, how far aside of a robot on a hallway's mid-line that hallway's walls and side openings lie:
  /// half hallway_max_width (the stated widest hallway, without the width tolerance widestHallway()
  /// adds for a measured width). A wall or opening farther aside is not the hallway's own (an open
  /// area's, or a room's far wall seen through a door). Every node that asks "is this beside my
  /// hallway" asks this.
  double hallwayReach() const { return 0.5 * hallway_max_width; }
  /// No hallway's mouth is this narrow: an opening of this width is a door by its width alone
  /// (or too narrow to pass: see door_min_width).
  bool doorByWidth(double width) const { return width < hallway_min_width - width_tolerance; }
  /// An opening of this width may still be a door (a double door) if it opens into a room.
  bool mayBeDoor(double width) const { return width <= door_max_width + width_tolerance; }
  /// The door test on one sighting: a door's width, and where a hallway's mouth could be as wide, a
  /// room behind.
  bool isDoor(double width, bool room_behind) const { return width >= door_min_width && opensAsDoor(width, room_behind); }
  /// The same without the narrowest door's width: a mean of sightings that each passed it.
  bool opensAsDoor(double width, bool room_behind) const {
    return doorByWidth(width) || (room_behind && mayBeDoor(width));
  }
  /// The door test on an opening tracked over scans: its mean width, and how many scans saw a room
  /// behind it (two: one stray return is no room).
  bool isDoorTracked(double mean_width, int room_sightings) const { return opensAsDoor(mean_width, room_sightings >= 2); }
  /// m per m of depth: how far beyond a mouth's edge the walls of a hallway whose mouth is as narrow
  /// as a door can run (cot of the steepest such hallway's angle to the wall, see above).
  double branchSpread() const {
    const double s = std::clamp(hallway_min_width / (door_max_width + width_tolerance), 1e-3, 1.0);
    return std::sqrt(1.0 - s * s) / s;
  }
  /// m, how far apart two widths of one opening measured from different places along a hallway
  /// may lie: each is within width_tolerance only with both jambs in view; from a grazing view the
  /// far jamb is hidden and the far edge is the next wall point seen. A measured value, not
  /// derived (a 0.7 m door was measured 1.3 m after a U-turn): see differentOpenings().
  static constexpr double kWidthSpread = 0.6;
  /// Two measured widths (> 0) farther apart than kWidthSpread: not one opening's measured from
  /// two places. An unmeasured width (<= 0) tells nothing apart.
  bool widthsApart(double width_a, double width_b) const {
    return width_a > 0.0 && width_b > 0.0 && std::abs(width_a - width_b) > kWidthSpread;
  }
  /// Two openings measured these widths are two (a door beside a hallway's branch on the same side),
  /// not one measured twice: their widths are apart (widthsApart) and only one is a door's.
  bool differentOpenings(double width_a, double width_b) const {
    return widthsApart(width_a, width_b) && doorByWidth(width_a) != doorByWidth(width_b);
  }
  /// Two measurements of these widths may be one opening measured twice: each is within
  /// width_tolerance of the true width.
  bool sameWidth(double width_a, double width_b) const { return std::abs(width_a - width_b) <= 2.0 * width_tolerance; }
  /// A door in a wall across a hallway (its end wall) has that wall on both sides: its frame is set
  /// in it, door_jamb_min at least, so the hallway is that much wider than the door on each side. An
  /// opening as wide as the hallway (within both widths' errors) spans it from side wall to side
  /// wall: the hallway's mouth (into a crossing or an open area), not a door.
  bool fitsInEndWall(double opening_width, double hallway_width) const {
    return opening_width + 2.0 * door_jamb_min <= hallway_width + 2.0 * width_tolerance;
  }
  /// m, the least distance from a door's centre to the wall it meets at a corner: half the narrowest
  /// door and its frame (door_jamb_min). A door this far or farther from a wall's line lies in another
  /// wall than that one (a side or back wall, not the wall of the door a room was entered by), and a
  /// door on a wall line lies beyond a side wall by at least this.
  double doorFromCorner() const { return 0.5 * door_min_width + door_jamb_min; }
  /// Range checks; false with the offending parameter in `error`.
  bool valid(std::string* error = nullptr) const {
    auto fail = [&](const char* why) {
      if (error) *error = why;
      return false;
    };
    if (!(door_min_width > 0.0 && door_max_width > door_min_width))
      return fail("building/door_min_width and building/door_max_width must satisfy 0 < min < max");
    if (!(hallway_min_width > door_min_width))
      return fail("building/hallway_min_width must be above building/door_min_width");
    if (!(hallway_max_width > hallway_min_width))
      return fail("building/hallway_max_width must be above building/hallway_min_width");
    if (!(width_tolerance >= 0.0 && width_tolerance < hallway_min_width - door_min_width))
      return fail("building/width_tolerance must be in [0, hallway_min_width - door_min_width)");
    if (!(door_jamb_min >= 0.0 && door_min_width + 2.0 * door_jamb_min < hallway_min_width + 2.0 * width_tolerance))
      return fail("building/door_jamb_min must be in [0, (hallway_min_width - door_min_width) / 2 + width_tolerance)");
    return true;
  }
};

/// Every building rule with its key in config/building.yaml (under the `building` namespace).
template <typename Visitor>
void visitBuildingRules(BuildingRules* r, Visitor&& visit) {
  visit("door_min_width", &r->door_min_width);
  visit("door_max_width", &r->door_max_width);
  visit("hallway_min_width", &r->hallway_min_width);
  visit("hallway_max_width", &r->hallway_max_width);
  visit("width_tolerance", &r->width_tolerance);
  visit("door_jamb_min", &r->door_jamb_min);
}

}  // namespace laser_features
