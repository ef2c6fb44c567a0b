#include "exploration/hallway_doors.h"

#include <algorithm>
#include <cmath>

namespace exploration {

using laser_features::inverse;
using laser_features::kPi;
using laser_features::normalizeAngle;
using laser_features::Pose2D;
using laser_features::transformPoint;
using laser_features::unitVector;

namespace {

// A tracked door's place from the robot (odometry `odom`), along the travel direction (`dir_robot`,
// robot frame) and to its left.
struct TravelFrame {
  TravelFrame(const Pose2D& odom, double dir_robot)
      : robot(odom.x, odom.y), heading(normalizeAngle(dir_robot + odom.theta)), u(unitVector(heading)),
        nrm(unitVector(heading + 0.5 * kPi)) {}
  double along(const Eigen::Vector2d& p) const { return (p - robot).dot(u); }
  double lateral(const Eigen::Vector2d& p) const { return (p - robot).dot(nrm); }
  Eigen::Vector2d robot;
  double heading;  // rad, odometry frame
  Eigen::Vector2d u, nrm;
};

}  // namespace

std::optional<double> HallwayDoors::wallLateral(const Pose2D& odom, double dir_robot, const HallwayView& v, int side,
                                                double travel) {
  const bool seen = side == 0 ? v.left_wall : v.right_wall;
  const double lateral = side == 0 ? v.left_lateral : -v.right_lateral;
  const Eigen::Vector2d nrm = unitVector(dir_robot + (side == 0 ? 0.5 : -0.5) * kPi);  // robot frame, towards the side
  if (seen) {
    wall_seen_odom_[side] = transformPoint(odom, Eigen::Vector2d(lateral * nrm));
    wall_seen_travel_[side] = travel;
    return lateral;
  }
  if (!wall_seen_odom_[side] || travel - wall_seen_travel_[side] > params_.wall_memory) return std::nullopt;
  return transformPoint(inverse(odom), *wall_seen_odom_[side]).dot(nrm);
}

HallwayDoors::Walls HallwayDoors::track(const Pose2D& odom, const std::vector<laser_features::Opening>& openings,
                                        double dir_robot, const HallwayView& v, double travel) {
  const Eigen::Vector2d nrm = unitVector(dir_robot + 0.5 * kPi);
  const Walls walls{{wallLateral(odom, dir_robot, v, 0, travel), wallLateral(odom, dir_robot, v, 1, travel)}};
  for (const auto& o : openings) {
    // Every opening that may be a door is tracked: whether it is one (a double door's width needs a
    // room seen behind it) is decided on the track, when it is passed.
    if (!(o.width >= rules_.door_min_width && rules_.mayBeDoor(o.width))) continue;
    const double lateral = o.center.dot(nrm);
    if (std::abs(lateral) > rules_.hallwayReach() || std::abs(lateral) < 0.4) continue;
    const double side = lateral > 0.0 ? 1.0 : -1.0;
    // Behind the wall on its side: a gap inside a room seen through its door (large_floor: a
    // "door" 1.7 m to the left of a hallway whose wall is 1.1 m away, tracked for 3 scans and
    // stopped for with the real door 0.5 m ahead; the robot drove into the wall).
    const std::optional<double>& wall = walls[side > 0.0 ? 0 : 1];
    if (wall && std::abs(lateral) > *wall + params_.wall_tolerance) continue;
    // A gap in the side wall the robot follows -- both its edges on that wall's line, within the
    // error of a measured edge (width_tolerance) -- needs no confidence from its edges' lines: that
    // wall supports it, as an end wall supports a gap in it (inEndWall). The wall beside a door next
    // to a corner (the hallway's end, a junction) may be shorter than any line, which halves
    // laser_features' confidence once or twice. A weak gap with an edge off the wall (seen past an
    // occluding jamb to a point in the room, or between things in front of the wall) is not the
    // door, and would pull its track off the wall.
    const auto onWall = [&](const Eigen::Vector2d& edge) {
      return std::abs(side * edge.dot(nrm) - *wall) <= rules_.width_tolerance;
    };
    const bool in_side_wall = wall && onWall(o.left) && onWall(o.right);
    const bool weak = o.confidence < params_.min_confidence;
    if (weak && !in_side_wall) continue;
    const double into = dir_robot + side * 0.5 * kPi;  // robot frame
    if (std::abs(normalizeAngle(o.theta - into)) > params_.tracks.side_angle) continue;
    const Eigen::Vector2d c = transformPoint(odom, o.center);
    const double into_odom = normalizeAngle(into + odom.theta);
    auto it = std::find_if(tracks_.begin(), tracks_.end(), [&](const DoorTrack& t) {
      return (t.centre_odom - c).norm() < params_.same_distance;
    });
    if (it == tracks_.end()) {
      DoorTrack t;
      t.centre_odom = c;
      t.into_odom = into_odom;
      t.width = o.width;
      t.sightings = 1;
      t.located_sightings = weak ? 0 : 1;
      t.room_sightings = o.room_behind ? 1 : 0;
      t.wall_lateral = wall ? *wall : -1.0;
      t.located = std::abs(o.center.dot(unitVector(dir_robot))) <= kAbeam * std::abs(lateral);
      // First seen already passed: behind where this stretch started, seen in the turn into it
      // (large_floor: a known room's door 1.2 m behind the T where the robot turned into hall_3,
      // entered as new 0.4 s after the turn).
      t.decided = o.center.dot(unitVector(dir_robot)) < -params_.tracks.enter_lag;
      tracks_.push_back(t);
      continue;
    }
    // Running mean of the position and width (the heading is the hallway's normal), of the
    // confident sightings once there are any: a weak one confirms the door, not where it is.
    if (!weak || it->located_sightings == 0) {
      const int n = weak ? it->sightings : it->located_sightings;
      const double k = 1.0 / double(std::min(n + 1, 20));
      it->centre_odom += k * (c - it->centre_odom);
      it->width += k * (o.width - it->width);
    }
    if (!weak) ++it->located_sightings;
    it->into_odom = into_odom;
    it->wall_lateral = wall ? *wall : -1.0;
    if (std::abs(o.center.dot(unitVector(dir_robot))) <= kAbeam * std::abs(lateral)) it->located = true;
    ++it->sightings;
    if (o.room_behind) ++it->room_sightings;
  }
  const Eigen::Vector2d robot(odom.x, odom.y);
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                              [&](const DoorTrack& t) { return (t.centre_odom - robot).norm() > params_.tracks.keep_distance; }),
               tracks_.end());
  return walls;
}

void HallwayDoors::roomVisited(const std::optional<Pose2D>& drift) {
  // The EKF's pose in a room is good to centimetres (its lines are metres long and seen from a few
  // metres), so a track moved by the drift it measured is where the track was before the visit: a
  // door beside the one entered (centres 1.2 m apart on one wall) stays another door when passed.
  if (!drift) {
    for (DoorTrack& t : tracks_) t.located = false;
    return;
  }
  for (DoorTrack& t : tracks_) {
    t.centre_odom = transformPoint(*drift, t.centre_odom);
    t.into_odom = normalizeAngle(t.into_odom + drift->theta);
  }
  for (std::optional<Eigen::Vector2d>& w : wall_seen_odom_)
    if (w) w = transformPoint(*drift, *w);
}

std::optional<DoorTrack> HallwayDoors::abeam(const Pose2D& odom, double dir_robot, double side) const {
  const TravelFrame f(odom, dir_robot);
  for (const DoorTrack& t : tracks_) {
    // A door by the building rules: an opening a hallway's mouth could be as wide as, with no room
    // seen behind it, is no door (a short narrow hallway is such a mouth).
    if (t.sightings < 2 || !rules_.isDoorTracked(t.width, t.room_sightings)) continue;
    // Within kSameDoorSpan along: the door abeam, not one farther on.
    if (std::abs(f.along(t.centre_odom)) <= kSameDoorSpan && f.lateral(t.centre_odom) * side > 0.0) return t;
  }
  return std::nullopt;
}

bool HallwayDoors::passed(const Pose2D& odom, double dir_robot, const Walls& walls, DoorTrack* door) {
  const TravelFrame f(odom, dir_robot);
  for (DoorTrack& t : tracks_) {
    if (t.decided || t.sightings < params_.tracks.min_sightings) continue;
    const double along = f.along(t.centre_odom);
    if (along > -params_.tracks.enter_lag) continue;
    if (along < -params_.tracks.enter_lag - 1.0) {  // seen only from behind: too late
      t.decided = true;
      continue;
    }
    if (offer(t, f.lateral(t.centre_odom), walls, f.robot, door)) return true;
  }
  return false;
}

bool HallwayDoors::besideEnd(const Pose2D& odom, double dir_robot, const Walls& walls, double free_ahead,
                             const std::array<bool, 2>& closed, bool turning_round, DoorTrack* door) {
  const TravelFrame f(odom, dir_robot);
  for (DoorTrack& t : tracks_) {
    if (t.decided || t.sightings < params_.tracks.min_sightings) continue;
    const double along = f.along(t.centre_odom), lateral = f.lateral(t.centre_odom);
    // Not passed (passed() has those), and in a side wall short of the end wall (a door lies on its
    // wall: wall_tolerance).
    const double min_along = turning_round ? params_.tracks.enter_lag : -params_.tracks.enter_lag;
    if (along <= min_along || along > free_ahead + params_.wall_tolerance) continue;
    if (!closed[lateral > 0.0 ? 0 : 1]) continue;  // the side the robot turns to: its way on
    if (offer(t, lateral, walls, f.robot, door)) return true;
  }
  return false;
}

bool HallwayDoors::opensAwayFrom(const DoorTrack& t, const Eigen::Vector2d& robot) {
  return (t.centre_odom - robot).dot(unitVector(t.into_odom)) > 0.0;
}

bool HallwayDoors::offer(DoorTrack& t, double lateral, const Walls& walls, const Eigen::Vector2d& robot, DoorTrack* door) {
  t.decided = true;
  if (!rules_.isDoorTracked(t.width, t.room_sightings)) return false;  // a hallway's mouth
  // A door opens away from the hallway the robot stands in: the robot is on its near side. Each
  // sighting's direction into the room points away from the robot; a track whose last sighting was
  // taken from elsewhere (in a turn at a junction, seen from another hallway) can point back at
  // the robot, and its room would be the hallway.
  if (!opensAwayFrom(t, robot)) return false;
  // Behind the wall known now, though tracked while none was (large_floor: just after a turn into
  // a hallway, a gap 1.58 m aside with the wall found 1.04 m aside by the time it was passed).
  const std::optional<double>& wall = walls[lateral > 0.0 ? 0 : 1];
  if (wall && std::abs(lateral) > *wall + params_.wall_tolerance) return false;
  // A door taken already on this stretch, tracked a second time: its first sightings from afar
  // lay beyond door_same_distance of the later ones (large_floor run 14: room_4_16's door entered
  // by a track of 5 sightings, and again by one of 97, 0.24 m from it, after visiting the room
  // across the hallway). Two tracks both located are one door only where their spans overlap.
  const bool taken_before = std::any_of(tracks_.begin(), tracks_.end(), [&](const DoorTrack& k) {
    const double span = k.located && t.located ? 0.5 * (k.width + t.width) : kSameDoorSpan;
    return k.taken && (k.centre_odom - t.centre_odom).norm() < span &&
           std::abs(normalizeAngle(k.into_odom - t.into_odom)) < 0.5;
  });
  if (taken_before) return false;
  t.taken = true;
  *door = t;
  return true;
}

std::optional<DoorTrack> HallwayDoors::inEndWall(const Pose2D& odom, const std::vector<laser_features::Opening>& openings,
                                                double dir_robot, const HallwayView& v) const {
  const Eigen::Vector2d u = unitVector(dir_robot), nrm = unitVector(dir_robot + 0.5 * kPi);
  // Both walls seen: the hallway's width is measured. Half of it from the mid-line; half the widest
  // hallway where a wall is not seen.
  const bool walls_seen = v.left_wall && v.right_wall;
  const double half = walls_seen ? 0.5 * v.width() : 0.5 * rules_.widestHallway();
  // The end wall is free_ahead away (a sector that sees through the door makes free_ahead the
  // wall's: HallwayView's wall_across); a door lies on its wall, as a side door does on its side's
  // (wall_tolerance).
  std::optional<DoorTrack> best;
  double best_lateral = 0.0;
  for (const auto& o : openings) {
    if (!rules_.isDoor(o.width, o.room_behind)) continue;
    const double ahead = o.center.dot(u), lateral = std::abs(o.center.dot(nrm) - v.centre_offset);
    if (ahead <= 0.0 || ahead > v.free_ahead + params_.wall_tolerance || lateral > half) continue;
    // A gap in the end wall itself (both walls seen, the end wall where the view ends) is a gap in a
    // wall whatever line support its edges have: the wall beside a door near a side wall may be
    // shorter than any line (door_jamb_min, 0.2 m), which halves laser_features' confidence. The
    // extractor's passage test (free space the robot's diameter deep behind it) stands. Elsewhere ahead, a gap
    // between unrelated surfaces is told from a door by its edges' support.
    const bool in_end_wall = walls_seen && std::abs(ahead - v.free_ahead) <= params_.wall_tolerance;
    if (o.confidence < params_.min_confidence && !in_end_wall) continue;
    if (std::abs(normalizeAngle(o.theta - dir_robot)) > params_.tracks.side_angle) continue;
    if (walls_seen && !rules_.fitsInEndWall(o.width, v.width())) continue;  // the hallway's mouth
    if (best && lateral >= best_lateral) continue;
    DoorTrack t;
    t.centre_odom = transformPoint(odom, o.center);
    t.into_odom = normalizeAngle(odom.theta + o.theta);  // the normal points away from the sensor: into the room
    t.width = o.width;
    t.sightings = 1;
    t.room_sightings = o.room_behind ? 1 : 0;
    best = t;
    best_lateral = lateral;
  }
  return best;
}

}  // namespace exploration
