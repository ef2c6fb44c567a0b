// How an opening seen along a hallway is tracked over scans, shared by every node that tracks
// openings: pomdp_topo's front end (which makes nodes of them) and the exploration's door tracker
// (which enters them). Two trackers with other values would disagree on which openings exist and
// which are beside the robot. One struct, one YAML (config/opening_tracks.yaml, loaded by every
// launch file into the `opening_tracks` namespace), one reader (building_rules_ros.h).
//
// ROS-free: the standard library only.
#pragma once

#include <cmath>
#include <string>

namespace laser_features {

struct OpeningTracks {
  // rad (25 deg), an opening whose normal lies within this of +-90 deg of the travel heading is a
  // side opening of the hallway (a door or a branch beside the robot); one more oblique is ahead
  // or behind (an end wall's door, a junction's far side).
  double side_angle = 0.44;
  // -, scans a track needs before it counts (observed, passed, offered for entering): a gap seen in
  // one or two scans is most often a grazing view between furniture and a wall.
  int min_sightings = 3;
  // m, tracks farther than this from the robot are dropped: beyond the range openings are tracked
  // at (pomdp_topo's max_feature_range), so a track is dropped only once it is out of use.
  double keep_distance = 8.0;
  // m, a side opening is passed once this far behind the robot: pomdp_topo's front end makes its
  // landmark (a door's node) then. A few scans' travel (0.05-0.1 m each), so that the opening is
  // seen abeam, where its position is best, before it is passed.
  double pass_lag = 0.2;
  // m, a door is entered once this far behind the robot: after it was passed (pomdp_topo has made
  // its node, which the entry marks explored), so more than pass_lag. The robot turns back to it.
  double enter_lag = 0.3;

  bool valid(std::string* error = nullptr) const {
    if (std::isfinite(side_angle) && side_angle > 0.0 && side_angle < M_PI / 2 && min_sightings >= 1 &&
        std::isfinite(keep_distance) && keep_distance > 0.0 && std::isfinite(pass_lag) && pass_lag >= 0.0 &&
        std::isfinite(enter_lag) && enter_lag > pass_lag && enter_lag < keep_distance)
      return true;
    if (error)
      *error = "opening_tracks/side_angle must be in (0, pi/2), opening_tracks/min_sightings >= 1, "
               "opening_tracks/keep_distance > 0, opening_tracks/pass_lag >= 0 and opening_tracks/enter_lag "
               "in (pass_lag, keep_distance): a door is entered after it is passed";
    return false;
  }
};

/// Every value with its key in config/opening_tracks.yaml (under the `opening_tracks` namespace).
template <typename Visitor>
void visitOpeningTracks(OpeningTracks* t, Visitor&& visit) {
  visit("side_angle", &t->side_angle);
  visit("min_sightings", &t->min_sightings);
  visit("keep_distance", &t->keep_distance);
  visit("pass_lag", &t->pass_lag);
  visit("enter_lag", &t->enter_lag);
}

}  // namespace laser_features
