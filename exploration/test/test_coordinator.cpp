// The coordinator's mode switching on a synthetic hallway: a door passed on a new stretch is
// entered (METRIC, a place requested); never while the belief is unconfident, nor right after the
// belief jumped across the graph (the paper's rule: no topological-to-metric switch unless sure).
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "exploration/coordinator.h"

using exploration::Coordinator;
using exploration::CoordinatorMode;
using exploration::Decision;
using exploration::GraphEdge;
using exploration::GraphNode;
using exploration::GraphOpening;
using exploration::Perception;
using exploration::Request;
using exploration::TopoGraph;
using exploration::TopoMode;
using exploration::TopoView;
using laser_features::Pose2D;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A hallway along +x between y = -1 and y = +1 with a 0.9 m door in the left wall at x = 5 (or,
// with `branch`, a 2.2 m hallway branching off to the north there).
struct Hallway {
  double door_x = 5.0;
  double door_width = 0.9;
  bool branch = false;
  bool gap_in_room = false;  // a 1.1 m gap 1.7 m to the left, 0.8 m before the door, seen from within 1 m
  bool left_wall_in_pieces = false;  // within 3 m of the door the left wall's lines are 0.5 m pieces (no wall)
  double left_wall_seen_from = -1e9;  // with the robot before this x, all of the left wall is in pieces
  double right_door_x = -1e9;         // a door on the right too (0.9 m wide), if set
  double right_door_far_shift = 0.0;  // seen from farther than 2.5 m, it appears this far further along
  double pillar_x = -1e9;             // a pillar of radius 0.15 m on the mid-line, if set
  double right_wall = -1.0;           // y of the right wall (a wider hallway, the robot off its middle)

  Perception perceive(double x, double t) const {
    Perception p;
    p.stamp = t;
    p.odom = Pose2D{x, 0.0, 0.0};
    auto line = [&](double x0, double x1, double y) {
      laser_features::LineSegment l;
      l.start = Eigen::Vector2d(x0 - x, y);
      l.end = Eigen::Vector2d(x1 - x, y);
      p.lines.push_back(l);
    };
    auto wall = [&](double x0, double x1, double y) {
      for (double wx = x0; wx <= x1; wx += 0.05) {
        if (std::abs(wx - x) < 8.0) p.points.emplace_back(wx - x, y);
      }
      const bool hidden = y > 0.0 && x < left_wall_seen_from;
      if (!(left_wall_in_pieces && y > 0.0) && !hidden) return line(x0, x1, y);
      const double lo = hidden ? x0 : std::max(x0, door_x - 3.0), hi = hidden ? x1 : std::min(x1, door_x + 3.0);
      if (lo >= hi) return line(x0, x1, y);
      if (lo > x0) line(x0, lo, y);
      for (double a = lo; a < hi; a += 0.5) line(a, std::min(a + 0.45, hi), y);
      if (hi < x1) line(hi, x1, y);
    };
    const double half = branch ? 1.1 : 0.5 * door_width;
    wall(-20.0, door_x - half, 1.0);
    wall(door_x + half, 40.0, 1.0);
    const bool right_door = right_door_x > -1e8;
    wall(-20.0, right_door ? right_door_x - 0.45 : 40.0, right_wall);
    if (right_door) wall(right_door_x + 0.45, 40.0, right_wall);
    if (pillar_x > -1e8 && std::abs(pillar_x - x) < 8.0) {
      for (int k = 0; k < 48; ++k) p.points.emplace_back(pillar_x - x + 0.15 * std::cos(k * kPi / 24), 0.15 * std::sin(k * kPi / 24));
    }
    // The room behind the door: its far wall 4 m away (the branch: 8 m of it in view).
    for (double wx = door_x - 2.0; wx <= door_x + 2.0; wx += 0.05) p.points.emplace_back(wx - x, branch ? 9.0 : 5.0);
    laser_features::Opening o;
    o.center = Eigen::Vector2d(door_x - x, 1.0);
    o.left = Eigen::Vector2d(door_x - x - half, 1.0);
    o.right = Eigen::Vector2d(door_x - x + half, 1.0);
    o.theta = 0.5 * kPi;
    o.width = 2.0 * half;
    o.kind = branch ? laser_features::OpeningKind::kJunction : laser_features::OpeningKind::kDoor;
    o.room_behind = !branch;  // the room's far wall beyond the door's edges (laser_features' test)
    o.confidence = 0.9;
    if (std::abs(door_x - x) < 6.0) p.openings.push_back(o);
    if (right_door && std::abs(right_door_x - x) < 6.0) {
      laser_features::Opening r = o;
      const double rx = right_door_x + (std::abs(right_door_x - x) > 2.5 ? right_door_far_shift : 0.0);
      r.center = Eigen::Vector2d(rx - x, -1.0);
      r.left = Eigen::Vector2d(rx - x + 0.45, -1.0);
      r.right = Eigen::Vector2d(rx - x - 0.45, -1.0);
      r.theta = -0.5 * kPi;
      r.width = 0.9;
      r.kind = laser_features::OpeningKind::kDoor;
      p.openings.push_back(r);
    }
    const double gap_x = door_x - 0.8;
    if (gap_in_room && std::abs(gap_x - x) < 1.0) {
      laser_features::Opening g = o;
      g.center = Eigen::Vector2d(gap_x - x, 1.7);
      g.left = g.center - Eigen::Vector2d(0.55, 0.0);
      g.right = g.center + Eigen::Vector2d(0.55, 0.0);
      g.width = 1.1;
      p.openings.push_back(g);
    }
    return p;
  }
};

TopoView view(TopoMode mode, bool confident) {
  TopoView v;
  v.valid = true;
  v.mode = mode;
  v.confident = confident;
  v.heading_valid = true;
  v.map_from_odom.theta = 0.0;
  return v;
}

struct DriveResult {
  bool metric = false;          // the coordinator switched to METRIC (or SWITCHING)
  bool place_requested = false;
  double x_at_switch = 0.0;
};

// Drives the robot along the hallway at 0.5 m/s (10 Hz ticks) from x0 to x1 with the given
// belief view per x; the robot stops when the coordinator says so.
template <typename ViewAt>
DriveResult drive(Coordinator* c, double x0, double x1, ViewAt view_at, const Hallway& h = Hallway()) {
  DriveResult r;
  double x = x0, t = 0.0;
  for (int i = 0; i < 400 && x < x1; ++i, t += 0.1) {
    const Decision d = c->update(h.perceive(x, t), view_at(x), false, false);
    for (const Request& q : d.requests) r.place_requested |= q.kind == Request::CreatePlace;
    if (d.mode == CoordinatorMode::Metric || d.mode == CoordinatorMode::Switching) {
      if (!r.metric) r.x_at_switch = x;
      r.metric = true;
    }
    if (!d.stop && d.has_goal && d.x > x) x += 0.05;
  }
  return r;
}

// An ideal robot free to move anywhere, one 0.1 s tick of it: 0.05 m towards the goal, facing that
// way, or at the goal 0.1 rad towards its heading. Nothing when the coordinator stops it.
void stepTowardsGoal(const Decision& d, Pose2D* robot) {
  if (d.stop || !d.has_goal) return;
  const Eigen::Vector2d to = Eigen::Vector2d(d.x, d.y) - Eigen::Vector2d(robot->x, robot->y);
  if (to.norm() > 0.01) {
    const Eigen::Vector2d step = to.norm() > 0.05 ? Eigen::Vector2d(0.05 * to.normalized()) : to;
    robot->x += step.x();
    robot->y += step.y();
    robot->theta = std::atan2(to.y(), to.x());
  } else if (d.theta) {
    robot->theta += std::max(-0.1, std::min(0.1, laser_features::normalizeAngle(*d.theta - robot->theta)));
  }
}

exploration::CoordinatorParams roomVisitParams() {
  exploration::CoordinatorParams params;
  params.room_visit.time_limit = 15.0;  // the hallway's room is empty: a short visit
  return params;
}

struct RoomVisits {
  Pose2D robot;
  int places = 0;
  int ticks = 0;
};

// Drives an ideal robot along the hallway of `h` to x = 12 m (at most `max_ticks` 0.1 s ticks),
// into the rooms the coordinator enters and out again; `before_tick(h, places so far)` may change
// the hallway as it goes. `room_drift` (m, along x): the odometry drifts this much in the first
// room (over its first 50 ticks after the EKF's first pose), the EKF's pose there seeing the room as
// it is; `ekf`: the EKF gives poses in the rooms (false: none, the drift is not measured).
RoomVisits driveVisitingRooms(Coordinator* c, Hallway* h, int max_ticks,
                              const std::function<void(Hallway*, int)>& before_tick = {}, double room_drift = 0.0,
                              bool ekf = true) {
  RoomVisits r;
  Pose2D origin;  // the place's frame (the robot's pose at its creation)
  double drift = 0.0;  // m, along x, the odometry's so far
  double t = 0.0;
  for (; r.ticks < max_ticks && r.robot.x < 12.0; ++r.ticks, t += 0.1) {
    if (before_tick) before_tick(h, r.places);
    Perception p = h->perceive(r.robot.x, t);
    // The hallway's features as seen from the robot's pose (perceive assumes y = 0, heading 0).
    p.odom = r.robot;
    p.room_pose_valid = ekf && c->currentPlace() >= 0;
    if (p.room_pose_valid && c->mode() != CoordinatorMode::Topological && r.places == 1)
      drift = std::min(room_drift, drift + room_drift / 50.0);
    p.room_pose = laser_features::compose(laser_features::inverse(origin),
                                          Pose2D{r.robot.x - drift, r.robot.y, r.robot.theta});
    const Decision d = c->update(p, view(TopoMode::Frontier, true), false, false);
    for (const Request& q : d.requests) {
      if (q.kind != Request::CreatePlace) continue;
      origin = r.robot;
      c->placeCreated(true, r.places++);
    }
    stepTowardsGoal(d, &r.robot);
  }
  return r;
}

}  // namespace

// The parameters' check names the first value out of range by its key, and the coordinator refuses
// parameters that fail it.
TEST(CoordinatorParams, AValueOutOfRangeIsRefusedByItsKey) {
  exploration::CoordinatorParams p;
  std::string why;
  EXPECT_TRUE(p.valid(&why)) << why;
  p.follow.lookahead = 0.2;
  EXPECT_FALSE(p.valid(&why));
  EXPECT_EQ(why, "lookahead must be > 0.3 m");
  p = exploration::CoordinatorParams();
  p.route.max_route_attempts = 0;
  p.follow.stall_time = 0.0;
  EXPECT_FALSE(p.valid(&why));
  EXPECT_EQ(why, "max_route_attempts must be >= 1");  // the first one out of range
  p = exploration::CoordinatorParams();
  p.mission.max_relocation_failures = -1;
  EXPECT_FALSE(p.valid(&why));
  EXPECT_NE(why.find("mission/max_relocation_failures"), std::string::npos) << why;
  p = exploration::CoordinatorParams();
  p.settle_time = -1.0;
  EXPECT_FALSE(p.valid());
  EXPECT_THROW(Coordinator{p}, std::invalid_argument);
}

// The robot seen by a turned scanner: the hallway's points and lines in the frame of a robot at x
// facing `yaw` (map frame = odometry frame, as the Hallway is drawn).
Perception perceiveFacing(const Hallway& h, double x, double yaw) {
  Perception p = h.perceive(x, 0.0);
  const Eigen::Rotation2Dd to_robot(-yaw);
  for (auto& q : p.points) q = to_robot * q;
  for (auto& l : p.lines) {
    l.start = to_robot * l.start;
    l.end = to_robot * l.end;
  }
  p.openings.clear();
  p.odom.theta = yaw;
  return p;
}

// A robot that starts facing across the hallway (a wall 1 m ahead, 21 deg off the bin across it,
// the way to either side 8 m) sets off along the hallway; one that starts facing along it sets off
// the way it faces.
TEST(Coordinator, AStartFacingAcrossTheHallwaySetsOffAlongIt) {
  Hallway h;
  h.door_x = 30.0;  // no door in view
  Coordinator across;
  const Perception facing_wall = perceiveFacing(h, 10.0, 0.5 * kPi - 0.37);
  across.update(facing_wall, view(TopoMode::Frontier, true), false, false);  // the start: decides
  const Decision d = across.update(facing_wall, view(TopoMode::Frontier, true), false, false);
  ASSERT_TRUE(d.has_goal && d.theta.has_value()) << across.state();
  EXPECT_EQ(across.state(), "turning");
  EXPECT_LT(std::abs(std::sin(*d.theta)), 1e-9) << *d.theta;  // along x, one way or the other
  Coordinator along;
  along.update(perceiveFacing(h, 10.0, 0.3), view(TopoMode::Frontier, true), false, false);
  const Decision e = along.update(perceiveFacing(h, 10.0, 0.3), view(TopoMode::Frontier, true), false, false);
  EXPECT_NE(along.state(), "turning");
  EXPECT_FALSE(e.theta.has_value() && std::abs(std::sin(*e.theta)) > 0.5);
}

// A pillar on the mid-line is no hallway end: the walls go on past it and a lane beside it is free,
// so the robot goes on to the door beyond it (it turned round at pillars in generated buildings).
TEST(Coordinator, APillarInTheHallwayIsNoEnd) {
  Hallway h;
  h.pillar_x = 3.0;
  Coordinator c;
  const DriveResult r = drive(&c, 0.0, 8.0, [](double) { return view(TopoMode::Frontier, true); }, h);
  EXPECT_TRUE(r.metric) << c.state();
  EXPECT_GE(r.x_at_switch, 5.0);
}

TEST(Coordinator, ADoorPassedOnANewStretchIsEntered) {
  Coordinator c;
  const DriveResult r = drive(&c, 0.0, 8.0, [](double) { return view(TopoMode::Frontier, true); });
  EXPECT_TRUE(r.metric);
  EXPECT_TRUE(r.place_requested);
  // Entered once passed: pomdp_topo makes the door's node when it is 0.2 m behind.
  EXPECT_GE(r.x_at_switch, 5.0 + 0.3 - 1e-9);
  EXPECT_LE(r.x_at_switch, 5.0 + 1.0);
}

namespace {

// On a new stretch of `h`, the robot stops for its door (at 5 m) once it is passed, not before
// (for a gap behind the wall, seen through the door).
void expectStoppedJustPastTheDoor(const Hallway& h, double x0 = 0.0) {
  Coordinator c;
  const DriveResult r = drive(&c, x0, 8.0, [](double) { return view(TopoMode::Frontier, true); }, h);
  EXPECT_TRUE(r.metric);
  EXPECT_GE(r.x_at_switch, 5.0 + 0.3 - 1e-9) << "stopped for the gap, before the door";
  EXPECT_LE(r.x_at_switch, 5.0 + 1.0);
}

}  // namespace

TEST(Coordinator, AGapBehindTheWallIsNoDoor) {
  // large_floor: an opening 1.7 m to the left of a hallway whose wall is 1.1 m away (a gap inside
  // the room, seen through its door) was tracked for 3 scans and stopped for with the real door
  // 0.5 m ahead; the robot drove into the wall and the room was missed.
  Hallway h;
  h.gap_in_room = true;
  expectStoppedJustPastTheDoor(h);
}

TEST(Coordinator, AGapBehindAWallSeenAMomentAgoIsNoDoor) {
  // large_floor: a 0.97 m "door" 1.63 m to the left of a hallway whose wall is 1.1 m away, with no
  // wall line seen on that side at the time (the wall is broken into short pieces by its doors):
  // the wall seen a few metres before still gates it.
  Hallway h;
  h.gap_in_room = true;
  h.left_wall_in_pieces = true;
  expectStoppedJustPastTheDoor(h);
}

TEST(Coordinator, AGapBehindAWallSeenOnlySinceIsNoDoor) {
  // large_floor (stop 20, run 10): just after turning into a hallway (its walls forgotten), a gap
  // behind the wall was tracked while no wall line was seen on that side; by the time it was
  // passed the wall was known 1.04 m aside, and the robot stopped for it 1.58 m to the side,
  // 0.75 m from the real door, drove at the wall and built a place in the hallway. A door is
  // entered only if it lies within door_wall_tolerance of its side's wall known when it is passed.
  Hallway h;
  h.gap_in_room = true;
  h.left_wall_seen_from = 4.3;
  expectStoppedJustPastTheDoor(h, 3.3);
}

TEST(Coordinator, ADoorFirstSeenBehindTheRobotIsNotEntered) {
  // large_floor (stop 20, run 11): turned at a T into a new stretch of hall_3, the robot stopped
  // 0.4 s later for a door 1.23 m behind it (a known room's, beyond the T) and mapped the room again.
  // A door seen first already behind the robot was not passed on this stretch.
  Coordinator c;
  const DriveResult behind = drive(&c, 6.2, 10.0, [](double) { return view(TopoMode::Frontier, true); });
  EXPECT_FALSE(behind.metric) << "entered at x " << behind.x_at_switch;
  Coordinator d;  // seen first just beside the robot, it is entered
  const DriveResult beside = drive(&d, 5.1, 10.0, [](double) { return view(TopoMode::Frontier, true); });
  EXPECT_TRUE(beside.metric);
}

TEST(Coordinator, ADoorTakenForAKnownOneIsNotEntered) {
  // pomdp_topo makes the door's node as the robot stops and takes it for a known node (small_loop
  // with one room: the ring's corners all look alike, the door tells them apart): no place is
  // created and the robot goes on along the hallway while the loop is checked.
  Coordinator c;
  Hallway h;
  bool place_requested = false, stopped = false;
  double x = 0.0, t = 0.0;
  for (int i = 0; i < 400 && x < 8.0; ++i, t += 0.1) {
    // The door's node (and the hypothesis) comes once the coordinator has decided to stop there.
    const Decision d = c.update(h.perceive(x, t), view(stopped ? TopoMode::LoopCheck : TopoMode::Frontier, true), false, false);
    stopped |= d.mode == CoordinatorMode::Switching;
    for (const Request& q : d.requests) place_requested |= q.kind == Request::CreatePlace;
    if (!d.stop && d.has_goal && d.x > x) x += 0.05;
  }
  EXPECT_FALSE(place_requested);
  EXPECT_GE(x, 8.0) << "the robot did not go on along the hallway";
  EXPECT_EQ(c.stats().doors_entered, 0);
  EXPECT_EQ(c.stats().doors_passed, 1);
}

TEST(Coordinator, ADoorWhoseLoopClosedInOneGoIsNotEnteredAgain) {
  // explore_restart: the robot stopped for a door on a new stretch, and pomdp_topo made the door's
  // node, took it for a known one and closed the loop in the same scan: the belief is localized at
  // that node, whose door is explored (its room mapped). Not entered; the robot goes on.
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{2, 0, 5.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, true, 7}}});
  g.addNode(GraphNode{1, 1, 10.0, 0.0, {GraphOpening{0.5 * kPi, 2.0, false}}});
  g.addEdge(GraphEdge{0, 0, 2, 0.0, 5.0});
  g.addEdge(GraphEdge{1, 2, 1, 0.0, 5.0});
  Coordinator c;
  c.setGraph(g);
  Hallway h;
  bool place_requested = false, stopped = false;
  double x = 0.0, t = 0.0;
  for (int i = 0; i < 400 && x < 8.0; ++i, t += 0.1) {
    TopoView v = view(TopoMode::Frontier, true);
    if (stopped) {
      v = view(TopoMode::Localized, true);
      v.position.valid = true;
      v.position.id = 1;  // on the edge 2 -> 1
      v.position.offset = x - 5.0;
    }
    const Decision d = c.update(h.perceive(x, t), v, false, false);
    stopped |= d.mode == CoordinatorMode::Switching;
    for (const Request& q : d.requests) place_requested |= q.kind == Request::CreatePlace;
    if (!d.stop && d.has_goal && d.x > x) x += 0.05;
  }
  EXPECT_TRUE(stopped);
  EXPECT_FALSE(place_requested);
  EXPECT_GE(x, 8.0) << "the robot did not go on along the hallway";
  EXPECT_EQ(c.stats().doors_entered, 0);
}

TEST(Coordinator, ADoorOnANewStretchThatTheFrontierNodeHasExploredIsNotEntered) {
  // large_floor: room_7_14's door, joined to junction 39 a metre off its centre and explored from
  // there, was passed again on a new stretch leaving 39; pomdp_topo (still on the frontier at 39)
  // takes it for 39's door. Not entered; with 39's door unexplored, or a node not received yet
  // (pomdp_topo made a new one for the door), it is.
  for (const int known : {0, 1, 2}) {  // explored at node 2, unexplored at node 2, node 2 unknown
    TopoGraph g;
    g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
    if (known < 2) g.addNode(GraphNode{2, 1, 4.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, known == 0, known == 0 ? 7 : -1}}});
    g.addEdge(GraphEdge{0, 0, 2, 0.0, 4.0});
    Coordinator c;
    c.setGraph(g);
    const DriveResult r = drive(&c, 0.0, 8.0, [](double x) {
      TopoView v = view(TopoMode::Frontier, true);
      v.position.valid = true;
      v.position.at_node = true;
      v.position.id = x < 4.0 ? 0 : 2;
      return v;
    });
    EXPECT_EQ(r.place_requested, known != 0) << "case " << known;
    EXPECT_EQ(c.stats().doors_passed, known != 0 ? 0 : 1) << "case " << known;
  }
}

TEST(Coordinator, TheDoorJustLeftIsNotEnteredAgain) {
  // large_floor: back on the hallway from room_2_12, pomdp_topo still on the frontier (where every
  // door passed is new), the robot tracked the door it had just come out of anew and entered the
  // room again. Here the odometry drifts 1.2 m east in the room, so back on the hallway the door
  // (and the whole hallway) appears 1.2 m further east than tracked on the way in (beyond
  // door_same_distance of that track). With the drift measured by the EKF in the room the track
  // moves with it; unmeasured, the track from before the visit is no longer located.
  for (const bool ekf : {true, false}) {
    Coordinator c(roomVisitParams());
    Hallway h;
    const RoomVisits r = driveVisitingRooms(
        &c, &h, 6000,
        [&](Hallway* hw, int places) { hw->door_x = places > 0 && c.mode() == CoordinatorMode::Topological ? 6.2 : 5.0; },
        1.2, ekf);
    ASSERT_GT(r.places, 0) << "the door was never entered; EKF " << ekf;
    EXPECT_GE(r.robot.x, 12.0) << "the robot did not go on along the hallway (" << r.ticks << " ticks); EKF " << ekf;
    EXPECT_EQ(r.places, 1) << "the room was entered again; EKF " << ekf;
    EXPECT_EQ(c.stats().doors_entered, 1) << "EKF " << ekf;
  }
}

TEST(Coordinator, ADoorTrackedTwiceIsEnteredOnce) {
  // large_floor run 14: hall_2's room_4_16 door (right) seen first from afar made a track that its
  // later sightings fell beyond; the robot entered the room by the second track, then the room
  // across (left), and coming back out stopped for the first track and mapped room_4_16 again.
  Coordinator c(roomVisitParams());
  Hallway h;
  h.door_x = 5.2;
  h.right_door_x = 4.8;
  h.right_door_far_shift = 1.05;
  const RoomVisits r = driveVisitingRooms(&c, &h, 9000);
  EXPECT_GE(r.robot.x, 12.0) << "the robot did not go on along the hallway (" << r.ticks << " ticks)";
  EXPECT_EQ(r.places, 2) << "a room was entered again";
}

TEST(Coordinator, ANewRoomsDoorIsTakenAsSeenFromInFrontOfIt) {
  // large_floor: room_3_18's door, tracked while the robot came out of the room across the hallway
  // and turned, lay 0.5 m east of where it is; the robot went to a point before the east jamb,
  // "explored" the hallway there and the room was missed. Here the door (5.0 m) is tracked at 5.5 m
  // from the hallway and seen where it is from the way to it: the robot goes through at 5.0 m.
  Coordinator c;
  Hallway h;
  Pose2D robot{0.0, 0.0, 0.0}, origin;
  bool created = false;
  double x_in_front = NAN;
  std::vector<Request> adds;
  double t = 0.0;
  for (int ticks = 0; ticks < 3000 && std::isnan(x_in_front); ++ticks, t += 0.1) {
    Perception p = h.perceive(robot.x, t);
    p.odom = robot;
    p.room_pose_valid = created;
    p.room_pose = laser_features::compose(laser_features::inverse(origin), robot);
    // The door's opening as seen from the robot's pose: 0.5 m east of it while on the hallway
    // (before the place is made), where it is once the robot goes to it.
    p.openings.clear();
    const double seen_x = created ? 5.0 : 5.5;
    laser_features::Opening o;
    o.center = laser_features::transformPoint(laser_features::inverse(robot), Eigen::Vector2d(seen_x, 1.0));
    o.left = o.center;  // (unused by the coordinator's door track)
    o.right = o.center;
    o.theta = laser_features::normalizeAngle(0.5 * kPi - robot.theta);
    o.width = 0.9;
    o.kind = laser_features::OpeningKind::kDoor;
    o.confidence = 0.9;
    if (std::abs(seen_x - robot.x) < 6.0) p.openings.push_back(o);
    const Decision d = c.update(p, view(TopoMode::Frontier, true), false, false);
    for (const Request& q : d.requests) {
      if (q.kind == Request::CreatePlace) {
        origin = robot;
        created = true;
        c.placeCreated(true, 0);
      }
      if (q.kind == Request::AddDoor) adds.push_back(q);
    }
    if (c.state().rfind("exploring the room", 0) == 0) x_in_front = robot.x;
    stepTowardsGoal(d, &robot);
  }
  ASSERT_TRUE(created) << "the door was never stopped for";
  ASSERT_FALSE(std::isnan(x_in_front)) << c.state();
  // The approach ends within 0.15 m of the point 0.6 m before the door on its axis.
  EXPECT_NEAR(x_in_front, 5.0, 0.16) << "in front of the door as tracked, not as it is";
  EXPECT_NE(c.state().find("door refined by"), std::string::npos) << c.state();
  // The EKF keeps the door as tracked from the hallway (a mission's relocation measures it so).
  ASSERT_EQ(adds.size(), 1u);
  EXPECT_NEAR(laser_features::transformPoint(origin, Eigen::Vector2d(adds[0].pose.x, adds[0].pose.y)).x(), 5.5, 0.05);
}

TEST(Coordinator, NeverMetricWhileTheBeliefIsUnconfident) {
  Coordinator c;
  const DriveResult r = drive(&c, 0.0, 8.0, [](double) { return view(TopoMode::Localized, false); });
  EXPECT_FALSE(r.metric);
  EXPECT_FALSE(r.place_requested);
  EXPECT_EQ(c.stats().doors_passed, 1);
  // Nor while a loop closure is being verified.
  Coordinator loop;
  EXPECT_FALSE(drive(&loop, 0.0, 8.0, [](double) { return view(TopoMode::LoopCheck, true); }).metric);
}

TEST(Coordinator, AKnownUnexploredDoorIsEnteredButNotRightAfterTheBeliefJumped) {
  // The graph: a hallway 0 -- 10 m -- 1 (east), with a door node 2 at x = 5 in between
  // (0 -> 2 -> 1) whose opening to the north is not explored, and a hallway end 3 40 m west of 0.
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{2, 0, 5.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, false}}});
  g.addNode(GraphNode{1, 2, 10.0, 0.0, {}});
  g.addNode(GraphNode{3, 2, -40.0, 0.0, {}});
  g.addEdge(GraphEdge{0, 0, 2, 0.0, 5.0});
  g.addEdge(GraphEdge{1, 2, 1, 0.0, 5.0});
  g.addEdge(GraphEdge{2, 3, 0, 0.0, 40.0});
  auto on = [](uint32_t edge, double offset) {
    TopoView v = view(TopoMode::Localized, true);
    v.position.valid = true;
    v.position.at_node = false;
    v.position.id = edge;
    v.position.offset = offset;
    v.position.heading = 0.0;
    return v;
  };
  // Tracked all along: the door (node 2) is entered.
  {
    Coordinator c;
    c.setGraph(g);
    const DriveResult r = drive(&c, 0.0, 8.0, [&](double x) { return x < 5.0 ? on(0, x) : on(1, x - 5.0); });
    EXPECT_TRUE(r.metric);
    EXPECT_EQ(c.stats().belief_jumps, 0);
  }
  // The belief first sits 39 m back, by node 3, and jumps to the door's edges 2 m before the
  // door: not acted on (6 m of travel needed), the door is passed.
  {
    Coordinator c;
    c.setGraph(g);
    const DriveResult r = drive(&c, 0.0, 8.0, [&](double x) {
      if (x < 3.0) return on(2, 1.0);
      return x < 5.0 ? on(0, x) : on(1, x - 5.0);
    });
    EXPECT_FALSE(r.metric);
    EXPECT_GE(c.stats().belief_jumps, 1);
  }
}

// The route turns into a branch where the belief puts the robot at the branch's node, unless a
// door is beside the robot there: then the belief is wrong (large_floor: a 2.2 m crossing 38 m west
// taken at a 1.2 m office door, whose room was then mapped as hallways for 1,000 s).
TEST(Coordinator, TheRouteTurnsIntoABranchButNotIntoADoorWhereTheBeliefPutsTheBranch) {
  // Start 0 at x = 0, junction 2 at x = 5 with a branch north to node 4 (unexplored beyond), an
  // explored hallway end 1 at x = 10.
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  g.addNode(GraphNode{2, 1, 5.0, 0.0, {GraphOpening{0.5 * kPi, 2.2, true}}});
  g.addNode(GraphNode{4, 2, 5.0, 10.0, {GraphOpening{0.5 * kPi, 2.2, false}}});
  g.addNode(GraphNode{1, 2, 10.0, 0.0, {}});
  g.addEdge(GraphEdge{0, 0, 2, 0.0, 5.0});
  g.addEdge(GraphEdge{1, 2, 4, 0.5 * kPi, 10.0});
  g.addEdge(GraphEdge{2, 2, 1, 0.0, 5.0});
  for (bool branch : {true, false}) {
    Hallway h;
    h.branch = branch;
    h.door_width = 1.6;  // a double door: as wide as a narrow hallway's mouth, it opens the side (a single door does not)
    Coordinator c;
    c.setGraph(g);
    bool turned = false;
    double x = 0.0, t = 0.0;
    for (int i = 0; i < 400 && x < 8.0 && !turned; ++i, t += 0.1) {
      TopoView v = view(TopoMode::Localized, true);
      v.position.valid = true;
      v.position.id = x < 5.0 ? 0 : 2;  // along edge 0, then past node 2 on edge 2 (the belief)
      v.position.offset = x < 5.0 ? x : x - 5.0;
      v.position.heading = 0.0;
      const Decision d = c.update(h.perceive(x, t), v, false, false);
      turned = d.theta && std::abs(laser_features::normalizeAngle(*d.theta - 0.5 * kPi)) < 0.1;
      if (!d.stop && d.has_goal && d.x > x) x += 0.05;
    }
    if (branch) {
      EXPECT_TRUE(turned) << "no turn into the branch: " << c.state();
      EXPECT_NEAR(x, 5.0, 1.0);
      EXPECT_EQ(c.stats().branch_turns_refused, 0);
    } else {
      EXPECT_FALSE(turned) << "turned into the door at x = " << x;
      EXPECT_GE(x, 8.0) << c.state();
      EXPECT_EQ(c.stats().branch_turns_refused, 1);
    }
  }
}

// A goal opening as wide as a hallway's mouth where a door of its width is beside the robot is that
// door (a double door the map builder took for a branch, seeing the room behind it in fewer
// sightings): it is entered as a room once passed, not refused as a wrong belief (building 15 of the
// benchmark: 26 refusals of a 1.64 m double door at the node whose 1.64 m opening was the goal, until
// the time limit; building 4: four, then the opening set aside and its rooms beyond missed).
TEST(Coordinator, AGoalOpeningAsWideAsTheDoorBesideTheRobotIsThatDoorAndEntered) {
  for (const double goal_width : {1.6, 1.7}) {
    // Start 0 at x = 0, junction 2 at x = 5 with an unexplored 1.6 m opening north, a hallway end 1
    // at x = 10; the door at x = 5 is a 1.6 m double door with a room behind it.
    TopoGraph g;
    g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
    g.addNode(GraphNode{2, 1, 5.0, 0.0, {GraphOpening{0.5 * kPi, goal_width, false}}});
    g.addNode(GraphNode{1, 2, 10.0, 0.0, {}});
    g.addEdge(GraphEdge{0, 0, 2, 0.0, 5.0});
    g.addEdge(GraphEdge{2, 2, 1, 0.0, 5.0});
    Hallway h;
    h.branch = false;
    h.door_width = 1.6;
    Coordinator c;
    c.setGraph(g);
    const DriveResult r = drive(&c, 0.0, 8.0, [&](double x) {
      TopoView v = view(TopoMode::Localized, true);
      v.position.valid = true;
      v.position.id = x < 5.0 ? 0 : 2;
      v.position.offset = x < 5.0 ? x : x - 5.0;
      v.position.heading = 0.0;
      return v;
    }, h);
    EXPECT_TRUE(r.metric) << goal_width << " m goal opening: " << c.state();
    EXPECT_NEAR(r.x_at_switch, 5.0, 1.0) << goal_width;
    EXPECT_EQ(c.stats().branch_turns_refused, 0) << goal_width;
  }
}

namespace {

// The graph of the hallway above, explored: start node 0 at x = 0, door node 2 at x = 5 whose
// north door (explored) leads to place 4, a hallway end 1 at x = 10.
TopoGraph exploredHallway() {
  TopoGraph g;
  g.addNode(GraphNode{0, 4, 0.0, 0.0, {}});
  // The place's frame is the odometry frame here: the door lies at (5, 1) in it, facing north.
  g.addNode(GraphNode{2, 0, 5.0, 0.0, {GraphOpening{0.5 * kPi, 0.9, true, 4, {5.0, 1.0, 0.5 * kPi}}}});
  g.addNode(GraphNode{1, 2, 10.0, 0.0, {}});
  g.addEdge(GraphEdge{0, 0, 2, 0.0, 5.0});
  g.addEdge(GraphEdge{1, 2, 1, 0.0, 5.0});
  return g;
}

TopoView onHallway(double x) {
  TopoView v = view(TopoMode::Localized, true);
  v.position.valid = true;
  v.position.id = x < 5.0 ? 0 : 1;
  v.position.offset = x < 5.0 ? x : x - 5.0;
  v.position.heading = 0.0;
  return v;
}

struct MissionRun {
  std::vector<Request> requests;
  Pose2D robot;
  Eigen::Vector2d ekf_shift = Eigen::Vector2d::Zero();  // the EKF's estimate minus the odometry
  int ticks = 0;
};

// An ideal robot (from `start`, 0.05 m or 0.1 rad per 0.1 s tick towards the goal, where `free`
// lets it) on the mission; the place frame is the odometry frame. `relocation(k)` is ekf_local_map's verdict on the k-th relocation.
// `correction_at_goal`: the EKF's estimate jumps by this (place frame) the first time the
// controller has reached a goal within 1 cm of `goal` (an EKF correction after the final turn).
// `correction_in_room`: it jumps by this 2 s after the relocation; from then on the EKF's pose
// comes with every `pose_every`-th scan only (the EKF lags; the others have none).
template <typename Verdict, typename EachTick>
MissionRun runMission(Coordinator* c, Verdict relocation, EachTick each_tick, const std::string& verdict = "test",
                      int max_ticks = 3000, const Eigen::Vector2d& correction_at_goal = Eigen::Vector2d::Zero(),
                      const Eigen::Vector2d& goal = Eigen::Vector2d::Zero(),
                      const Eigen::Vector2d& correction_in_room = Eigen::Vector2d::Zero(), int pose_every = 1,
                      const Pose2D& start = Pose2D(), const std::function<bool(const Pose2D&)>& free = nullptr) {
  Hallway h;
  MissionRun run;
  run.robot = start;
  bool corrected = false;
  double t = 0.0;
  int relocations = 0;
  int relocated_at = -1;
  bool reached = false;
  for (; run.ticks < max_ticks && c->missionActive(); ++run.ticks, t += 0.1) {
    Perception p = h.perceive(run.robot.x, t);
    p.odom = run.robot;
    const bool lagging = relocated_at >= 0 && run.ticks > relocated_at + 20;
    if (relocated_at >= 0 && run.ticks == relocated_at + 20) run.ekf_shift += correction_in_room;
    p.room_pose_valid = c->currentPlace() >= 0 && (!lagging || run.ticks % pose_every == 0);
    if (reached && !corrected && (Eigen::Vector2d(run.robot.x, run.robot.y) + run.ekf_shift - goal).norm() < 0.01) {
      corrected = true;
      run.ekf_shift += correction_at_goal;
    }
    p.room_pose = run.robot;
    p.room_pose.x += run.ekf_shift.x();
    p.room_pose.y += run.ekf_shift.y();
    const Decision d = c->update(p, onHallway(run.robot.x), reached, false);
    for (const Request& q : d.requests) {
      run.requests.push_back(q);
      if (q.kind == Request::Relocate) {
        c->relocationResult(q.place_id, relocation(relocations++), verdict);
        relocated_at = run.ticks;
      }
    }
    each_tick(c, run.ticks);
    reached = false;
    if (d.stop || !d.has_goal) continue;
    const Eigen::Vector2d to(d.x - run.robot.x, d.y - run.robot.y);
    // The controller's "reached": at the goal's position and heading (as a real one, at rest).
    reached = to.norm() < 0.005 && (!d.theta || std::abs(laser_features::normalizeAngle(*d.theta - run.robot.theta)) < 0.01);
    if (to.norm() > 0.01) {
      const Eigen::Vector2d step = to.norm() > 0.05 ? Eigen::Vector2d(0.05 * to.normalized()) : to;
      Pose2D next = run.robot;
      next.x += step.x();
      next.y += step.y();
      if (!free || free(next)) run.robot = next;
    } else if (d.theta) {
      const double e = laser_features::normalizeAngle(*d.theta - run.robot.theta);
      run.robot.theta += std::max(-0.1, std::min(0.1, e));
    }
  }
  return run;
}

template <typename Verdict>
MissionRun runMission(Coordinator* c, Verdict relocation) {
  return runMission(c, relocation, [](Coordinator*, int) {});
}

int count(const std::vector<Request>& requests, Request::Kind kind) {
  int n = 0;
  for (const Request& r : requests) n += r.kind == kind;
  return n;
}

exploration::CoordinatorParams missionParams() {
  exploration::CoordinatorParams params;
  params.explore = false;
  return params;
}

// Until the coordinator is idle (waiting for a mission) at the start of the hallway.
void startIdle(Coordinator* c) {
  Hallway h;
  for (int i = 0; i < 5 && !c->idle(); ++i) c->update(h.perceive(0.0, 0.1 * i), onHallway(0.0), false, false);
}

// The explored hallway, idle at its start, then a mission to `place`.
bool startMissionOnHallway(Coordinator* c, int place, const Pose2D& goal, std::string* why) {
  c->setGraph(exploredHallway());
  startIdle(c);
  return c->startMission(place, goal, why);
}

}  // namespace

TEST(CoordinatorMission, AnUnknownPlaceOrARunningExplorationIsRefusedWithTheReason) {
  Coordinator exploring;
  exploring.setGraph(exploredHallway());
  std::string why;
  EXPECT_FALSE(exploring.startMission(4, Pose2D{5.0, 3.0, 0.0}, &why));
  EXPECT_NE(why.find("exploration is running"), std::string::npos) << why;

  Coordinator c(missionParams());
  c.setGraph(exploredHallway());
  startIdle(&c);
  ASSERT_TRUE(c.idle());
  EXPECT_FALSE(c.startMission(7, Pose2D{0.0, 0.0, 0.0}, &why));
  EXPECT_NE(why.find("place 7 is unknown"), std::string::npos) << why;
  EXPECT_NE(why.find("known places: 4"), std::string::npos) << why;
  EXPECT_FALSE(c.startMission(4, Pose2D{NAN, 0.0, 0.0}, &why));
  EXPECT_FALSE(c.missionActive());
}

TEST(CoordinatorMission, GoesAlongTheHallwayRelocatesAtTheDoorAndReachesTheGoal) {
  Coordinator c(missionParams());
  std::string why;
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.0, 3.0, 0.5 * kPi}, &why)) << why;
  const MissionRun run = runMission(&c, [](int) { return true; });
  ASSERT_TRUE(c.missionOutcome().finished);
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  EXPECT_NEAR(run.robot.x, 5.0, 0.03);
  EXPECT_NEAR(run.robot.y, 3.0, 0.03);
  ASSERT_EQ(count(run.requests, Request::Relocate), 1);
  for (const Request& r : run.requests) {
    if (r.kind != Request::Relocate) continue;
    EXPECT_EQ(r.place_id, 4);
    EXPECT_EQ(r.door_id, 2);
    // The robot stopped just past the door (x in 5.3 .. 6.3, on the mid-line): in the door's
    // frame (x into the room, y to its left) it is 1 m before it and 0.3 .. 1.3 m to the right.
    EXPECT_NEAR(r.pose.x, -1.0, 0.05);
    EXPECT_LT(r.pose.y, -0.25);
    EXPECT_GT(r.pose.y, -1.35);
  }
  EXPECT_EQ(count(run.requests, Request::CreatePlace), 0) << "a mission maps nothing new";
  EXPECT_EQ(count(run.requests, Request::RecordOpening), 0);
  EXPECT_GT(c.missionOutcome().path_length, 5.0);
  EXPECT_EQ(c.mode(), CoordinatorMode::Metric) << "idle in the goal's room";

  // A second mission to the same place: straight to the new goal, no relocation.
  ASSERT_TRUE(c.startMission(4, Pose2D{4.0, 2.5, 0.0}, &why)) << why;
  const MissionRun again = runMission(&c, [](int) { return true; });
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  EXPECT_EQ(count(again.requests, Request::Relocate), 0);
}

TEST(CoordinatorMission, AnEkfCorrectionAtTheGoalIsDrivenOutToWithinTheTolerance) {
  // At the goal, the EKF moves its estimate by 2 cm (less than mission/accept_distance): the goal
  // is sent again and the mission ends with the estimate within mission/goal_tolerance, not 2 cm off.
  Coordinator c(missionParams());
  std::string why;
  const Eigen::Vector2d goal(5.0, 3.0);
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{goal.x(), goal.y(), 0.5 * kPi}, &why)) << why;
  const MissionRun run = runMission(&c, [](int) { return true; }, [](Coordinator*, int) {}, "test", 3000,
                                    Eigen::Vector2d(0.0, -0.02), goal);
  ASSERT_TRUE(c.missionOutcome().finished);
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  EXPECT_NEAR(run.ekf_shift.y(), -0.02, 1e-12) << "the correction happened";
  const Eigen::Vector2d estimate = Eigen::Vector2d(run.robot.x, run.robot.y) + run.ekf_shift;
  EXPECT_LE((estimate - goal).norm(), missionParams().mission.goal_tolerance + 1e-9) << c.missionOutcome().message;
}

TEST(CoordinatorMission, AScanWithoutTheEkfsPoseIsPlacedByTheOdometrySinceTheLastOne) {
  // missions_small_loop (CI, machine loaded: scans late): the EKF corrected its estimate in the
  // room, then lagged; the scans without its pose were placed by the odometry since the
  // relocation, 0.15 m and 0.5 rad off, and the goal moved between the two every other scan: the
  // robot stalled 0.15 m from it for 20 s. Placed by the odometry since the EKF's last pose, the
  // goal stays put and is reached.
  Coordinator c(missionParams());
  std::string why;
  const Eigen::Vector2d goal(5.0, 3.0);
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{goal.x(), goal.y(), 0.5 * kPi}, &why)) << why;
  const MissionRun run = runMission(&c, [](int) { return true; }, [](Coordinator*, int) {}, "test", 3000,
                                    Eigen::Vector2d::Zero(), goal, Eigen::Vector2d(0.15, 0.0), 2);
  ASSERT_TRUE(c.missionOutcome().finished);
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  const Eigen::Vector2d estimate = Eigen::Vector2d(run.robot.x, run.robot.y) + run.ekf_shift;
  EXPECT_LE((estimate - goal).norm(), missionParams().mission.accept_distance) << c.missionOutcome().message;
}

TEST(CoordinatorMission, AFailedRelocationResetsTheBeliefAndIsGivenUpAfterTheLimit) {
  // Every relocation fails (the wrong room each time): the belief is reset and the robot goes
  // back to the hallway; after max_relocation_failures + 1 failures the mission fails.
  exploration::CoordinatorParams params = missionParams();
  params.mission.max_relocation_failures = 0;
  Coordinator c(params);
  std::string why;
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.0, 3.0, 0.0}, &why)) << why;
  const MissionRun run = runMission(&c, [](int) { return false; });
  ASSERT_TRUE(c.missionOutcome().finished);
  EXPECT_FALSE(c.missionOutcome().success);
  EXPECT_NE(c.missionOutcome().message.find("relocation"), std::string::npos) << c.missionOutcome().message;
  EXPECT_EQ(c.missionOutcome().relocation_failures, 1);
  EXPECT_EQ(count(run.requests, Request::ClosePlace), 1);
  EXPECT_LT(run.robot.y, 0.5) << "the robot must not enter a room it could not relocate in";
  EXPECT_EQ(c.mode(), CoordinatorMode::Topological);
}

TEST(CoordinatorMission, ACancelledMissionEndsAtOnceAndClosesThePlaceItRelocatedIn) {
  Coordinator c(missionParams());
  std::string why;
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.0, 3.0, 0.0}, &why)) << why;
  // Drive until the relocation is asked for; no verdict comes.
  Hallway h;
  double x = 0.0, t = 0.0;
  bool relocating = false;
  for (int i = 0; i < 400 && !relocating; ++i, t += 0.1) {
    const Decision d = c.update(h.perceive(x, t), onHallway(x), false, false);
    for (const Request& q : d.requests) relocating |= q.kind == Request::Relocate;
    if (!d.stop && d.has_goal && d.x > x) x += 0.05;
  }
  ASSERT_TRUE(relocating);
  c.cancelMission("cancelled by the client");
  EXPECT_FALSE(c.missionActive());
  EXPECT_FALSE(c.missionOutcome().success);
  EXPECT_EQ(c.missionOutcome().message, "cancelled by the client");
  const Decision d = c.update(h.perceive(x, t), onHallway(x), false, false);
  EXPECT_EQ(count(d.requests, Request::ClosePlace), 1);
  EXPECT_TRUE(d.stop);
  EXPECT_TRUE(c.idle());
}

// A robot that cannot get out of a room (its way out blocked) is never taken to be on the hallway:
// a mission that went on from inside the room followed the room as a hallway, and every later
// mission failed from there. The mission ends saying why, the robot in the room; the next mission
// leaves it afresh.
TEST(CoordinatorMission, AMissionThatCannotLeaveTheRoomEndsThereAndTheNextOneLeavesIt) {
  Coordinator c(missionParams());
  TopoGraph g = exploredHallway();  // and place 5 behind a south door at the hallway's end
  g.addNode(GraphNode{1, 2, 10.0, 0.0, {GraphOpening{-0.5 * kPi, 0.9, true, 5, {10.0, -1.0, -0.5 * kPi}}}});
  c.setGraph(g);
  startIdle(&c);
  std::string why;
  ASSERT_TRUE(c.startMission(4, Pose2D{5.0, 3.0, 0.0}, &why)) << why;
  MissionRun run = runMission(&c, [](int) { return true; });
  ASSERT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  // To place 5: the way out of place 4 (its door's line at y = 1) is shut.
  const Pose2D in_room = run.robot;
  ASSERT_TRUE(c.startMission(5, Pose2D{10.0, -3.0, 0.0}, &why)) << why;
  bool on_hallway_inside = false;
  const auto shut = [&](const Pose2D& next) { return next.y >= 1.3; };
  const auto watch = [&](Coordinator* co, int) { on_hallway_inside |= co->mode() == CoordinatorMode::Topological; };
  run = runMission(&c, [](int) { return true; }, watch, "test", 30000, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(),
                   Eigen::Vector2d::Zero(), 1, in_room, shut);
  EXPECT_FALSE(c.missionActive());
  EXPECT_FALSE(c.missionOutcome().success);
  EXPECT_NE(c.missionOutcome().message.find("could not leave place 4 through its door"), std::string::npos)
      << c.missionOutcome().message;
  EXPECT_FALSE(on_hallway_inside) << "the room was taken for the hallway";
  EXPECT_EQ(c.mode(), CoordinatorMode::Metric);
  // The next mission, the way out open: out of place 4 onto the hallway.
  ASSERT_TRUE(c.startMission(5, Pose2D{10.0, -3.0, 0.0}, &why)) << why;
  run = runMission(&c, [](int) { return true; }, [](Coordinator*, int) {}, "test", 1500, Eigen::Vector2d::Zero(),
                   Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), 1, run.robot);
  EXPECT_LT(run.robot.y, 0.5) << c.state();
  EXPECT_EQ(c.mode(), CoordinatorMode::Topological) << c.state();
}

TEST(CoordinatorMission, AGoalJustInsideTheDoorIsReached) {
  // The goal lies 0.4 m past the door line, within entry_depth (0.7 m): the robot goes through the
  // door on its axis once, then back to the goal, and does not swing between the two.
  Coordinator c(missionParams());
  std::string why;
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.3, 1.4, 0.0}, &why)) << why;
  const MissionRun run = runMission(&c, [](int) { return true; });
  ASSERT_TRUE(c.missionOutcome().finished);
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  EXPECT_NEAR(run.robot.x, 5.3, 0.03);
  EXPECT_NEAR(run.robot.y, 1.4, 0.03);
}

TEST(CoordinatorMission, ARelocationThatSeesTooLittleFromTheHallwayIsTriedAgainInFrontOfTheDoor) {
  // From the hallway the matched lines are all parallel (ekf_local_map keeps the relocation
  // pending): the robot moves in front of the door, facing in, where the next verdict succeeds.
  Coordinator c(missionParams());
  std::string why;
  ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.0, 3.0, 0.5 * kPi}, &why)) << why;
  int relocation_tick = -1;
  Pose2D at_success;
  const MissionRun run = runMission(
      &c, [&](int) { return false; },
      [&](Coordinator* co, int tick) {
        if (relocation_tick < 0 && c.state().find("trying again in front of the door") != std::string::npos)
          relocation_tick = tick;
        if (relocation_tick >= 0 && tick == relocation_tick + 40) co->relocationResult(4, true, "success");
      },
      "matched lines (nearly) parallel");
  ASSERT_GE(relocation_tick, 0) << "no second try in front of the door";
  EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
  EXPECT_EQ(c.missionOutcome().relocation_failures, 0);
  EXPECT_EQ(count(run.requests, Request::ResetBelief), 0);
  EXPECT_NEAR(run.robot.y, 3.0, 0.03);
}

TEST(CoordinatorMission, AJointlyIncompatibleRelocationFromTheHallwayIsAskedAgainInFrontOfTheDoor) {
  // The first verdict, from where the robot stopped past the door, is "matches jointly
  // incompatible" (the door seen off): a second relocation is asked for from in front of the door,
  // facing in; it succeeds and the mission goes on with no belief reset. Two such verdicts are the
  // wrong room: one relocation failure (with max_relocation_failures 0 the mission ends there).
  for (const bool second_ok : {true, false}) {
    exploration::CoordinatorParams params = missionParams();
    params.mission.max_relocation_failures = 0;
    Coordinator c(params);
    std::string why;
    ASSERT_TRUE(startMissionOnHallway(&c, 4, Pose2D{5.0, 3.0, 0.5 * kPi}, &why)) << why;
    const MissionRun run = runMission(&c, [&](int k) { return k == 1 && second_ok; }, [](Coordinator*, int) {},
                                      "matches jointly incompatible");
    ASSERT_TRUE(c.missionOutcome().finished);
    ASSERT_EQ(count(run.requests, Request::Relocate), 2) << second_ok;
    std::vector<Pose2D> asked;
    for (const Request& r : run.requests)
      if (r.kind == Request::Relocate) asked.push_back(r.pose);
    // The second: 0.6 m in front of the door (x = -0.6 in its frame), on its axis, facing in.
    EXPECT_NEAR(asked[1].x, -0.6, 0.1);
    EXPECT_NEAR(asked[1].y, 0.0, 0.1);
    EXPECT_NEAR(asked[1].theta, 0.0, 0.1);
    EXPECT_LT(asked[0].y, -0.25) << "the first from where the robot stopped, past the door";
    if (second_ok) {
      EXPECT_TRUE(c.missionOutcome().success) << c.missionOutcome().message;
      EXPECT_EQ(count(run.requests, Request::ResetBelief), 0);
    } else {
      EXPECT_FALSE(c.missionOutcome().success);
      EXPECT_EQ(c.missionOutcome().relocation_failures, 1);
      EXPECT_EQ(count(run.requests, Request::ResetBelief), 0) << "max_relocation_failures 0: the mission ends";
    }
  }
}

// Out of a room only once past its door's line: a robot blocked at its door on the way out (a
// narrow door, the door placed off) that went on as on a hallway took the room for hallways,
// circled it and reported the exploration complete (generated buildings 8 and 10). It tries again
// from where it stands; after three tries ending inside, the exploration stops and says why.
TEST(Coordinator, AWayOutThatEndsInsideTheRoomIsTriedAgainAndNeverTakenForTheHallway) {
  for (const int blocked_exits : {1, 1000}) {
    SCOPED_TRACE(blocked_exits);
    Coordinator c(roomVisitParams());
    Hallway h;
    Pose2D robot, origin;
    int places = 0, exits = 0, ticks = 0;
    bool was_exiting = false, topological_inside = false;
    for (double t = 0.0; ticks < 30000 && robot.x < 12.0 && c.mode() != CoordinatorMode::Done; ++ticks, t += 0.1) {
      Perception p = h.perceive(robot.x, t);
      p.odom = robot;
      p.room_pose_valid = c.currentPlace() >= 0;
      p.room_pose = laser_features::compose(laser_features::inverse(origin), robot);
      const bool exiting = c.state() == "through the door back to the hallway";
      if (exiting && !was_exiting) ++exits;
      was_exiting = exiting;
      const bool leaving = exiting || c.state().find("leaving the room by its door") != std::string::npos;
      // The door (left wall, y = 1) lets the robot through only after `blocked_exits` ways out.
      const bool shut = leaving && exits <= blocked_exits;
      const bool held = shut && robot.y <= 1.31;
      const Decision d = c.update(p, view(TopoMode::Frontier, true), false, held);
      for (const Request& q : d.requests) {
        if (q.kind != Request::CreatePlace) continue;
        origin = robot;
        c.placeCreated(true, places++);
      }
      Pose2D next = robot;
      stepTowardsGoal(d, &next);
      if (!(shut && next.y < 1.3 && robot.y >= 1.3)) robot = next;
      topological_inside |= c.mode() == CoordinatorMode::Topological && robot.y > 1.1;
    }
    ASSERT_GE(places, 1) << "the door was never entered";
    EXPECT_FALSE(topological_inside) << "the room was taken for the hallway";
    if (blocked_exits == 1) {
      EXPECT_EQ(exits, 2);
      EXPECT_GE(robot.x, 12.0) << "the robot did not go on along the hallway (" << c.state() << ")";
    } else {
      EXPECT_EQ(exits, 3);
      EXPECT_EQ(c.mode(), CoordinatorMode::Done);
      EXPECT_NE(c.state().find("could not leave place 0 through its door"), std::string::npos) << c.state();
    }
  }
}

// Generated buildings 12 and 20: the robot started facing a double door across the hallway, the
// view through it (a room 4 m deep) was longer than the hallway either way, and the robot set off
// into the room as along a hallway. The hallway it stands in runs between the walls beside it.
// Also in a 3.6 m hallway with the robot 1 m from the door's wall (2.6 m from the other: more than
// half of any hallway's width), and with the side walls of a room 2.8 m wide (narrower than that
// hallway) seen through the door.
TEST(Coordinator, AStartFacingADoubleDoorAcrossAShortHallwaySetsOffAlongTheHallway) {
  for (const double right_wall : {-1.0, -2.6}) {
    SCOPED_TRACE(right_wall);
    Hallway h;
    h.door_width = 1.6;
    h.right_wall = right_wall;
    Perception p = perceiveFacing(h, h.door_x, 0.5 * kPi - 0.37);
    for (const double side : {-1.4, 1.4}) {  // the room's side walls, from 1.2 m behind its door
      laser_features::LineSegment l;
      const Eigen::Rotation2Dd rot(-(0.5 * kPi - 0.37));
      l.start = rot * Eigen::Vector2d(side, 2.2);
      l.end = rot * Eigen::Vector2d(side, 4.9);
      p.lines.push_back(l);
    }
    // The hallway ends 3 m either way (end walls seen as points only).
    const Eigen::Rotation2Dd to_robot(-(0.5 * kPi - 0.37));
    for (double y = right_wall; y <= 1.0; y += 0.05) {
      p.points.push_back(to_robot * Eigen::Vector2d(3.0, y));
      p.points.push_back(to_robot * Eigen::Vector2d(-3.0, y));
    }
    Coordinator c;
    c.update(p, view(TopoMode::Frontier, true), false, false);  // the start: decides
    const Decision d = c.update(p, view(TopoMode::Frontier, true), false, false);
    ASSERT_TRUE(d.has_goal && d.theta.has_value()) << c.state();
    EXPECT_EQ(c.state(), "turning");
    EXPECT_LT(std::abs(std::sin(*d.theta)), 1e-9) << *d.theta;  // along x, one way or the other
  }
}

// "Complete" only when nothing was given up: a room left at its time limit is not all mapped, so
// once nothing else is left to explore the exploration ends incomplete and says why; with nothing
// given up it ends complete.
TEST(Coordinator, AnExplorationThatLeftARoomAtItsTimeLimitEndsIncompleteSayingWhy) {
  for (const bool left_early : {true, false}) {
    SCOPED_TRACE(left_early);
    exploration::CoordinatorParams params = roomVisitParams();
    if (left_early) params.room_visit.time_limit = 1.0;  // s: left before the room is covered
    Coordinator c(params);
    Hallway h;
    const RoomVisits r = driveVisitingRooms(&c, &h, 6000);
    EXPECT_EQ(r.places, 1);
    EXPECT_EQ(c.stats().rooms_left_early, left_early ? 1 : 0);
    c.setGraph(exploredHallway());  // every opening explored, the belief on it
    Decision d;
    for (int i = 0; i < 20 && c.mode() != CoordinatorMode::Done; ++i)
      d = c.update(h.perceive(8.0, 1000.0 + 0.1 * i), onHallway(8.0), false, false);
    ASSERT_EQ(c.mode(), CoordinatorMode::Done) << c.state();
    if (left_early) {
      EXPECT_NE(c.state().find("exploration stopped: no unexplored opening is left, but 0 opening(s) were given up "
                               "unreached, 0 door(s) into rooms behind rooms given up and 1 room(s) left at their time limit"),
                std::string::npos)
          << c.state();
    } else {
      EXPECT_EQ(c.state(), "exploration complete");
    }
  }
}
