// Building assumptions that several nodes decide with (DESIGN.md: thresholds come from the robot and
// from stated building ranges, never from one world). One struct, one YAML (config/building.yaml,
// loaded by every launch file into the `building` namespace), one reader: laser_features classifies
// openings with it, pomdp_topo types its nodes with it, the coordinator picks doors to enter with it.
//
// Hallways are 1.5-4.0 m wide.
// Doors: office, lab and school floors have single doors 0.7-1.2 m and double doors 1.4-1.8 m wide;
// hallways are 1.5-4.0 m wide. Width alone cannot tell a 1.6 m double door from a 1.5 m hallway, so
// an opening wider than door_max_width (1.3 m: above every single door, below every hallway) is
// taken as a junction; a double door is then a junction until the structure is read from geometry
// (a clearance minimum between two wider regions).
//
// ROS-free: the standard library only.
#pragma once

#include <string>

namespace laser_features {

struct BuildingRules {
  double door_min_width = 0.7;  // m, narrowest door (and opening) there is: the narrowest single door
  double door_max_width = 1.3;  // m, widest opening that is a door; wider ones are junctions (see above)

  /// An opening of this width is a door, not a junction (nor too narrow to be either).
  bool isDoorWidth(double width) const { return width >= door_min_width && width <= door_max_width; }
  /// Widths tell a door from a junction: `width` is at most a door's.
  bool doorWide(double width) const { return width <= door_max_width; }
  /// Range checks; false with the offending parameter in `error`.
  bool valid(std::string* error = nullptr) const {
    if (!(door_min_width > 0.0 && door_max_width > door_min_width)) {
      if (error) *error = "building/door_min_width and building/door_max_width must satisfy 0 < min < max";
      return false;
    }
    return true;
  }
};

/// Every building rule with its key in config/building.yaml (under the `building` namespace).
template <typename Visitor>
void visitBuildingRules(BuildingRules* r, Visitor&& visit) {
  visit("door_min_width", &r->door_min_width);
  visit("door_max_width", &r->door_max_width);
}

}  // namespace laser_features
