// The hallway seen in a scan: free distances, open sides, walls and the mid-line.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "exploration/hallway_follower.h"
#include "exploration/hallway_view.h"
#include "exploration/oblique_hallways.h"
#include "segment_world.h"

using exploration::HallwayViewParams;
using laser_features::BuildingRules;
using exploration::viewHallway;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Points every 2 cm along a segment.
void addWall(std::vector<Eigen::Vector2d>* pts, std::vector<laser_features::LineSegment>* lines, Eigen::Vector2d a,
             Eigen::Vector2d b) {
  const int n = int((b - a).norm() / 0.02);
  for (int i = 0; i <= n; ++i) pts->push_back(a + (b - a) * double(i) / n);
  laser_features::LineSegment l;
  l.start = a;
  l.end = b;
  lines->push_back(l);
}

}  // namespace

TEST(HallwayView, CentredInAStraightHallway) {
  // Robot 0.3 m left of the centre of a 2 m hallway along +x, with a wall 4 m ahead.
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-5.0, 0.7}, {4.0, 0.7});
  addWall(&pts, &lines, {-5.0, -1.3}, {4.0, -1.3});
  addWall(&pts, &lines, {4.0, -1.3}, {4.0, 0.7});
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_NEAR(v.free_ahead, 4.0, 0.05);
  EXPECT_FALSE(v.open_left);
  EXPECT_FALSE(v.open_right);
  ASSERT_TRUE(v.left_wall && v.right_wall);
  EXPECT_NEAR(v.width(), 2.0, 1e-9);
  EXPECT_NEAR(v.centre_offset, -0.3, 1e-9);
  ASSERT_TRUE(v.wall_direction_valid);
  EXPECT_NEAR(v.wall_direction, 0.0, 1e-9);
}

TEST(HallwayView, RefinesTheDirectionFromTheWalls) {
  // The same hallway seen from a robot turned by 0.1 rad: the walls run at -0.1 rad.
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  const double a = -0.1;
  const Eigen::Vector2d u(std::cos(a), std::sin(a)), n(-std::sin(a), std::cos(a));
  addWall(&pts, &lines, -5.0 * u + 1.0 * n, 5.0 * u + 1.0 * n);
  addWall(&pts, &lines, -5.0 * u - 1.0 * n, 5.0 * u - 1.0 * n);
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  ASSERT_TRUE(v.wall_direction_valid);
  EXPECT_NEAR(v.wall_direction, a, 1e-6);
}

TEST(HallwayView, AnLCornerOpensOneSideOnly) {
  // The end of a hallway along +x turning left (+y): wall ahead at 1 m, right wall, left open.
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-5.0, -1.0}, {1.0, -1.0});
  addWall(&pts, &lines, {1.0, -1.0}, {1.0, 8.0});
  addWall(&pts, &lines, {-5.0, 1.0}, {-1.0, 1.0});
  addWall(&pts, &lines, {-1.0, 1.0}, {-1.0, 8.0});
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_NEAR(v.free_ahead, 1.0, 0.02);
  EXPECT_TRUE(v.open_left);
  EXPECT_FALSE(v.open_right);
}

TEST(HallwayView, ADoorBesideTheRobotDoesNotOpenTheSide) {
  // A 0.9 m door in the left wall (1 m away) right beside the robot, a room behind it.
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-5.0, 1.0}, {-0.45, 1.0});
  addWall(&pts, &lines, {0.45, 1.0}, {5.0, 1.0});
  addWall(&pts, &lines, {-5.0, -1.0}, {5.0, -1.0});
  addWall(&pts, &lines, {-2.0, 5.0}, {2.0, 5.0});
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_FALSE(v.open_left);
  (void)kPi;
}

namespace {

// A pillar of radius r at (x, y): points every 2 cm of its circumference (no line: too short).
void addPillar(std::vector<Eigen::Vector2d>* pts, double x, double y, double r) {
  for (int k = 0; k < 80; ++k) pts->emplace_back(x + r * std::cos(k * kPi / 40), y + r * std::sin(k * kPi / 40));
}

}  // namespace

// A hallway ends where its walls end, not where an obstacle narrower than it stands: a pillar 1 m
// ahead on the mid-line of a 2.6 m hallway leaves a lane beside it and the walls reach on past it;
// an end wall 1 m ahead stops the walls, with or without a door in it.
TEST(HallwayView, APillarAheadIsNoEndButAnEndWallIs) {
  const double clearance = 0.35;  // the robot's radius and margin
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-5.0, 1.3}, {12.0, 1.3});
  addWall(&pts, &lines, {-5.0, -1.3}, {12.0, -1.3});
  addPillar(&pts, 1.25, 0.0, 0.25);
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_LT(v.free_ahead, 1.3);
  EXPECT_TRUE(v.wallsReach(v.free_ahead + 1.3));
  const exploration::Lane lane = exploration::freestLane(pts, 0.0, v, clearance);
  EXPECT_GT(lane.free, 10.0);
  EXPECT_GT(std::abs(lane.lateral), 0.25 + clearance - 1e-9);  // beside the pillar
  EXPECT_LT(std::abs(lane.lateral), 1.3 - clearance + 1e-9);   // inside the walls

  for (const double door : {0.0, 0.9}) {
    std::vector<Eigen::Vector2d> end_pts;
    std::vector<laser_features::LineSegment> end_lines;
    addWall(&end_pts, &end_lines, {-5.0, 1.3}, {1.0, 1.3});
    addWall(&end_pts, &end_lines, {-5.0, -1.3}, {1.0, -1.3});
    if (door > 0.0) {
      addWall(&end_pts, &end_lines, {1.0, -1.3}, {1.0, -door / 2});
      addWall(&end_pts, &end_lines, {1.0, door / 2}, {1.0, 1.3});
      addWall(&end_pts, &end_lines, {1.0, door / 2}, {5.0, door / 2 + 2.0});  // the room behind, walls away
    } else {
      addWall(&end_pts, &end_lines, {1.0, -1.3}, {1.0, 1.3});
    }
    const auto e = viewHallway(end_pts, end_lines, 0.0, HallwayViewParams());
    EXPECT_FALSE(e.wallsReach(e.free_ahead + 1.3)) << door;
  }
}

// A hallway's wall runs on past a door in it: a pillar ahead with doors in the walls beside it (the
// wall's lines broken by gaps narrower than the narrowest hallway's mouth) is no wall across the
// hallway, and a lane beside it goes on. A 3 m hallway, the robot 0.8 m from its right wall (the
// left wall too far aside to be seen as the hallway's), a 0.4 m pillar 1.45 m ahead and 0.67 m to
// the left, a door in the right wall from 0.1 to 0.95 m ahead and one in the left wall beside the
// pillar.
TEST(HallwayView, ADoorBesideAPillarIsNoWallAcross) {
  for (const double door_end : {0.95, 1.4}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines;
    addWall(&pts, &lines, {-6.0, -0.8}, {0.1, -0.8});  // right wall, a door, the wall on
    addWall(&pts, &lines, {door_end, -0.8}, {2.45, -0.8});
    addWall(&pts, &lines, {3.6, -0.8}, {12.0, -0.8});
    addWall(&pts, &lines, {-6.0, 2.2}, {0.85, 2.2});  // left wall, a door beside the pillar
    addWall(&pts, &lines, {1.75, 2.2}, {12.0, 2.2});
    addPillar(&pts, 1.45, 0.67, 0.2);
    const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
    EXPECT_FALSE(v.wall_across) << "door to " << door_end;
    const exploration::Lane lane = exploration::freestLane(pts, 0.0, v, 0.35);
    EXPECT_GT(lane.free, 10.0) << "door to " << door_end;
  }
  // The same wall broken by a crossing hallway's mouth (1.5 m) where the door was: the walls do not
  // run on, and a wall across ahead (a room's front wall past the crossing) ends the hallway.
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-6.0, -0.8}, {0.1, -0.8});
  addWall(&pts, &lines, {1.6, -0.8}, {12.0, -0.8});
  addWall(&pts, &lines, {1.6, -0.8}, {1.6, -0.45});  // the front wall across, a 0.9 m door in it
  addWall(&pts, &lines, {1.6, 0.45}, {1.6, 2.2});
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_TRUE(v.wall_across);
}

namespace {

Eigen::Vector2d dirOf(double a) { return {std::cos(a), std::sin(a)}; }

// A 2 m hallway along +x (walls y = +-1) whose end turns into a wing at `angle` (rad, to the right
// for < 0): the wing's right wall starts where the hallway's right wall ends at x = 0.5.
void addWingEnd(std::vector<Eigen::Vector2d>* pts, std::vector<laser_features::LineSegment>* lines, double angle) {
  const Eigen::Vector2d d = dirOf(angle), n(-d.y(), d.x());
  const Eigen::Vector2d right0(0.5, -1.0), left0 = right0 + 2.0 * n;
  addWall(pts, lines, {-6.0, -1.0}, right0);
  addWall(pts, lines, right0, right0 + 9.0 * d);
  addWall(pts, lines, {-6.0, 1.0}, {left0.x(), 1.0});
  addWall(pts, lines, {left0.x(), 1.0}, left0);
  addWall(pts, lines, left0, left0 + 9.0 * d);
}

}  // namespace

// A wing at 30-60 degrees to the building's axes is the way on from the main hallway's end.
TEST(HallwayView, AWingLeavingAHallwaysEndAtAnAngleIsTheWayOn) {
  for (const double angle : {-0.52, -0.79, -1.05, 0.79}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines;
    addWingEnd(&pts, &lines, angle);
    exploration::HallwayView v;
    v.end_centre = Eigen::Vector2d(0.5 + (angle < 0.0 ? 0.0 : 0.0), 0.0);
    const std::vector<exploration::ObliqueWay> ways =
        exploration::obliqueHallways(pts, lines, v, 0.0, HallwayViewParams(), 4.0, 4.1);
    ASSERT_EQ(ways.size(), 1u) << angle;
    EXPECT_NEAR(ways[0].direction, angle, 1e-6);
  }
}

// The wall on the inner side of a turn into a wing starts at the turn's corner and is seen edge-on
// from the hallway's end: its points are in the scan, too few for a line. One wall along the way and
// the points across within a hallway's width make it a hallway; the piece of end wall cut at a slant
// between the hallway's outer wall and the wing's is no second way.
TEST(HallwayView, AWingWhoseInnerWallIsSeenEdgeOnIsTheWayOn) {
  for (const double angle : {-0.52, -0.7, -0.9}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines, inner;
    const Eigen::Vector2d d = dirOf(angle), n(-d.y(), d.x());
    const Eigen::Vector2d right0(0.5, -0.85), left0 = right0 + 1.7 * n;  // a 1.7 m hallway and wing
    addWall(&pts, &lines, {-8.0, -0.85}, right0);
    addWall(&pts, &inner, right0, right0 + 9.0 * d);  // its points only
    addWall(&pts, &lines, {-8.0, 0.85}, {0.5, 0.85});
    addWall(&pts, &lines, {0.5, 0.85}, left0);  // the mouth's slanted piece
    addWall(&pts, &lines, left0, left0 + 9.0 * d);
    exploration::HallwayView v;
    v.end_centre = Eigen::Vector2d(0.0, 0.0);
    const std::vector<exploration::ObliqueWay> ways =
        exploration::obliqueHallways(pts, lines, v, 0.0, HallwayViewParams(), 4.0, 4.1);
    ASSERT_EQ(ways.size(), 1u) << angle;
    EXPECT_NEAR(ways[0].direction, angle, 0.03) << angle;
  }
}

// A wing's mouth bent at the hallway's end (its outer wall goes on from the hallway's, its inner wall
// starts past a piece cut at a slant) or a wing leaving backwards beside the end wall lies beyond
// the crossing's expected centre: the way is found from on towards the end wall, where the robot
// still fits. The robot stands at the end's stopping distance, as where it turns.
TEST(HallwayView, AWingThroughABentMouthIsSeenFromOnTowardsTheEndWall) {
  for (const double angle : {-1.03, -0.9}) {  // 59 and 52 deg to the right
    exploration::test::SegmentWorld world;
    const Eigen::Vector2d d = dirOf(angle), n(-d.y(), d.x());
    const Eigen::Vector2d right0(1.2, -0.78), left0 = right0 + 1.55 * n;  // a 1.55 m hallway and wing
    // Walls 0.1 m thick, as the simulator's: their faces and end caps.
    const auto wall = [&](Eigen::Vector2d a, Eigen::Vector2d b) {
      const Eigen::Vector2d t = 0.05 * (b - a).normalized(), m(-t.y(), t.x());
      const Eigen::Vector2d c[4] = {a - t + m, b + t + m, b + t - m, a - t - m};
      for (int i = 0; i < 4; ++i) world.wall(c[i].x(), c[i].y(), c[(i + 1) % 4].x(), c[(i + 1) % 4].y());
    };
    wall({-8.0, -0.78}, right0);
    wall(right0, right0 + 9.0 * d);
    wall(right0, {1.2, -12.0});  // a room's wall beside the wing
    wall({-8.0, 0.77}, {1.2, 0.77});
    wall({1.2, 0.77}, {1.2, 6.0});  // a room's wall across the hallway's end
    wall({1.2, 0.77}, left0);       // the mouth's piece cut at a slant
    wall(left0, left0 + 9.0 * d);
    // The scan from the robot (what it occludes matters here) and the walls' lines, robot frame.
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines;
    const auto look = [&](double x) {
      const Eigen::Vector2d at(x, 0.0);
      pts.clear();
      lines.clear();
      for (int k = 0; k < 720; ++k) {
        const Eigen::Vector2d u = dirOf(k * kPi / 360.0);
        const double r = world.raycast(at, u);
        if (r < 15.0) pts.push_back(r * u);
      }
      for (const exploration::test::Segment& w : world.walls) {
        if ((w.b - w.a).norm() < 0.3) continue;  // an end cap: no line
        laser_features::LineSegment l;
        l.start = w.a - at;
        l.end = w.b - at;
        lines.push_back(l);
      }
      return exploration::viewHallway(pts, lines, 0.0, HallwayViewParams());
    };
    // Along the hallway to where the robot stops at its end (HallwayFollowerParams::end_distance).
    const double end_distance = exploration::HallwayFollowerParams().end_distance;
    double x = -3.0;
    exploration::HallwayView v = look(x);
    while (v.free_ahead >= end_distance && x < 1.0) v = look(x += 0.05);
    const std::vector<exploration::ObliqueWay> ways =
        exploration::obliqueHallways(pts, lines, v, 0.0, HallwayViewParams(), 4.0, 4.1);
    ASSERT_EQ(ways.size(), 1u) << angle << " free ahead " << v.free_ahead;
    // The wing's way, told apart from any other (ways closer than the wall tolerance are one); the
    // follower takes its walls' direction once in it.
    EXPECT_NEAR(ways[0].direction, angle, 0.5 * HallwayViewParams().wall_parallel_tolerance) << angle;
  }
}

// A door in the end wall seen at a slant opens a corridor into the room behind it, but no walls run
// along that corridor: no way on. Nor is a plain dead end.
TEST(HallwayView, ADoorInTheEndWallAtASlantIsNoWingNorIsADeadEnd) {
  for (const double door : {0.0, 1.2, 1.8}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines;
    addWall(&pts, &lines, {-6.0, 1.0}, {2.0, 1.0});
    addWall(&pts, &lines, {-6.0, -1.0}, {2.0, -1.0});
    if (door > 0.0) {
      addWall(&pts, &lines, {2.0, -1.0}, {2.0, 1.0 - door});
      // The room behind: 6 m deep, 7 m wide.
      addWall(&pts, &lines, {2.1, 1.0}, {2.1, 3.5});
      addWall(&pts, &lines, {2.1, 3.5}, {8.1, 3.5});
      addWall(&pts, &lines, {8.1, 3.5}, {8.1, -3.5});
      addWall(&pts, &lines, {8.1, -3.5}, {2.1, -3.5});
      addWall(&pts, &lines, {2.1, -3.5}, {2.1, -1.0});
    } else {
      addWall(&pts, &lines, {2.0, -1.0}, {2.0, 1.0});
    }
    exploration::HallwayView v;
    v.end_centre = Eigen::Vector2d(1.0, 0.0);
    EXPECT_TRUE(exploration::obliqueHallways(pts, lines, v, 0.0, HallwayViewParams(), 4.0, 4.1).empty()) << door;
  }
}

// A hallway's branch is open beside the robot wherever the robot's corridor fits through its mouth,
// however narrow the branch is against the hallway (1.5-1.6 m off 2.6 m); a door is narrower than
// any hallway's mouth.
TEST(HallwayView, ANarrowBranchOffAWideHallwayOpensTheSideADoorDoesNot) {
  for (const double mouth : {1.5, 1.6, 2.0, 1.2, 0.9}) {
    for (const double abeam : {-0.3, 0.0, 0.3}) {  // the robot's offset along the hallway from the mouth's centre
      std::vector<Eigen::Vector2d> pts;
      std::vector<laser_features::LineSegment> lines;
      const double half = 0.5 * mouth, wall = 1.3;  // a 2.6 m hallway, the robot on its mid-line
      addWall(&pts, &lines, {-6.0 - abeam, wall}, {-half - abeam, wall});
      addWall(&pts, &lines, {half - abeam, wall}, {6.0 - abeam, wall});
      addWall(&pts, &lines, {-half - abeam, wall}, {-half - abeam, wall + 6.0});  // the branch (or room) behind
      addWall(&pts, &lines, {half - abeam, wall}, {half - abeam, wall + 6.0});
      addWall(&pts, &lines, {-6.0, -wall}, {6.0, -wall});
      const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
      const bool hallway = mouth >= 1.4;
      EXPECT_EQ(v.open_left, hallway) << mouth << " m mouth, " << abeam << " m along";
      EXPECT_FALSE(v.open_right);
    }
  }
}

// A side opens only where a hallway's mouth is: a door as wide as a single door gets (up to
// hallway_min_width - width_tolerance) never opens it, beside the robot or at a hallway's end, in a
// hallway as narrow as 1.5 m, where the side sector sees through the door into the room behind.
TEST(HallwayView, ADoorNeverOpensASideEvenInANarrowHallway) {
  for (const double hallway : {1.5, 2.0, 3.0}) {
    for (const double door : {0.7, 0.9, 1.2, 1.35}) {
      std::vector<Eigen::Vector2d> pts;
      std::vector<laser_features::LineSegment> lines;
      const double wall = 0.5 * hallway, half = 0.5 * door;
      // The door in the left wall beside the robot, a 4 x 4 m room behind it; the hallway ends in a
      // wall 1.6 m ahead with another door in its right wall beside the end.
      addWall(&pts, &lines, {-6.0, wall}, {-half, wall});
      addWall(&pts, &lines, {half, wall}, {1.6, wall});
      addWall(&pts, &lines, {-2.0, wall}, {-2.0, wall + 4.0});
      addWall(&pts, &lines, {2.0, wall}, {2.0, wall + 4.0});
      addWall(&pts, &lines, {-2.0, wall + 4.0}, {2.0, wall + 4.0});
      const double end = 1.6, right_door = 1.6 - wall;  // the right door's centre abeam of the end's centre
      addWall(&pts, &lines, {-6.0, -wall}, {right_door - half, -wall});
      addWall(&pts, &lines, {right_door + half, -wall}, {end, -wall});
      addWall(&pts, &lines, {right_door - 2.0, -wall - 4.0}, {right_door + 2.0, -wall - 4.0});
      addWall(&pts, &lines, {end, -wall - 4.0}, {end, wall});
      const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
      EXPECT_FALSE(v.open_left) << door << " m door beside the robot, " << hallway << " m hallway";
      EXPECT_FALSE(v.end_open_right) << door << " m door at the end, " << hallway << " m hallway";
    }
  }
}

// At an L corner the side hallway's far wall is in line with the end wall. A side hallway narrower
// than the robot's (both 1.5-4.0 m wide) has its mouth between the crossing's expected centre (half
// the robot's hallway short of the end) and the end wall, not about that centre: its side is open.
TEST(HallwayView, ANarrowerSideHallwayAtAnEndOpensItsSide) {
  for (const double own : {1.5, 2.4, 3.5}) {
    for (const double branch : {1.5, 2.0, 3.0}) {
      for (const int side : {1, -1}) {
        for (const double end : {1.0, 1.3}) {  // the robot stops about a metre short of the end wall
          std::vector<Eigen::Vector2d> pts;
          std::vector<laser_features::LineSegment> lines;
          const double s = side, wall = 0.5 * own;
          addWall(&pts, &lines, {-6.0, s * wall}, {end - branch, s * wall});  // the wall the branch leaves
          addWall(&pts, &lines, {end - branch, s * wall}, {end - branch, s * 8.0});
          addWall(&pts, &lines, {-6.0, -s * wall}, {end, -s * wall});
          addWall(&pts, &lines, {end, -s * wall}, {end, s * 8.0});  // the end wall, the branch's far wall
          const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
          const std::string at = std::to_string(branch) + " m branch off a " + std::to_string(own) + " m hallway, side " +
                                 std::to_string(side) + ", end " + std::to_string(end) + " m ahead";
          EXPECT_NEAR(v.free_ahead, end, 0.05) << at;
          EXPECT_EQ(v.end_open_left, side > 0) << at;
          EXPECT_EQ(v.end_open_right, side < 0) << at;
        }
      }
    }
  }
}

// A hallway ends at a wall across it even where a door in that wall lies on the mid-line: the
// sector ahead sees through the door, but no lane as wide as the narrowest hallway's mouth is free
// past the wall and the hallway's walls stop there. A hallway that narrows to the narrowest width
// goes on.
TEST(HallwayView, AnEndWallWithADoorOnTheMidLineEndsTheHallway) {
  for (const double hallway : {1.5, 2.0, 3.0}) {
    for (const double door : {0.8, 1.0, 1.3}) {
      std::vector<Eigen::Vector2d> pts;
      std::vector<laser_features::LineSegment> lines;
      const double wall = 0.5 * hallway, end = 2.5, half = 0.5 * door;
      addWall(&pts, &lines, {-6.0, wall}, {end, wall});
      addWall(&pts, &lines, {-6.0, -wall}, {end, -wall});
      addWall(&pts, &lines, {end, wall}, {end, half});  // the end wall, the door in its middle
      addWall(&pts, &lines, {end, -half}, {end, -wall});
      addWall(&pts, &lines, {end, 3.0}, {end + 5.0, 3.0});  // the room behind it
      addWall(&pts, &lines, {end, -3.0}, {end + 5.0, -3.0});
      addWall(&pts, &lines, {end + 5.0, -3.0}, {end + 5.0, 3.0});
      const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
      EXPECT_NEAR(v.free_ahead, end, 0.05) << door << " m door, " << hallway << " m hallway";
    }
  }
  // A 3 m hallway narrowing to 1.5 m (its right wall steps in, 2.5 m ahead), the robot on the
  // narrow part's mid-line: the hallway goes on past the step (the sector ahead meets the 1.5 m
  // part's walls 4.3 m ahead).
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-6.0, 0.75}, {12.0, 0.75});
  addWall(&pts, &lines, {-6.0, -2.25}, {2.5, -2.25});
  addWall(&pts, &lines, {2.5, -2.25}, {2.5, -0.75});
  addWall(&pts, &lines, {2.5, -0.75}, {12.0, -0.75});
  addWall(&pts, &lines, {12.0, -0.75}, {12.0, 0.75});
  const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  EXPECT_GT(v.free_ahead, 4.0);
}

// An end wall with a door, and behind it a room in line with the hallway (its side walls continue
// the hallway's, a wall's thickness on): the wall's lines break only for the end wall's thickness,
// but the end wall meets them there (a corner), so the hallway ends at it.
TEST(HallwayView, AnEndWallsCornerEndsTheHallwayWhereARoomsWallsLineUpBeyondIt) {
  for (const double hallway : {1.5, 2.0, 3.0}) {
    for (const double door : {0.8, 1.0}) {
      std::vector<Eigen::Vector2d> pts;
      std::vector<laser_features::LineSegment> lines;
      const double wall = 0.5 * hallway, end = 2.5, half = 0.5 * door, behind = end + 0.1;
      addWall(&pts, &lines, {-6.0, wall}, {end, wall});
      addWall(&pts, &lines, {-6.0, -wall}, {end, -wall});
      addWall(&pts, &lines, {end, wall}, {end, half});  // the end wall, the door in its middle
      addWall(&pts, &lines, {end, -half}, {end, -wall});
      addWall(&pts, &lines, {behind, wall}, {behind + 5.0, wall});  // the room, in line
      addWall(&pts, &lines, {behind, -wall}, {behind + 5.0, -wall});
      addWall(&pts, &lines, {behind + 5.0, -wall}, {behind + 5.0, wall});
      const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
      EXPECT_NEAR(v.free_ahead, end, 0.05) << door << " m door, " << hallway << " m hallway";
      EXPECT_TRUE(v.wall_across) << door << " m door, " << hallway << " m hallway";
    }
  }
}

// A room straight across a crossing, as narrow as the hallway that leads to it and in line with it
// (its side walls at the hallway's walls' offsets), entered by a door in its front wall: the room's
// walls line up with the hallway's, but they do not run on unbroken past its front wall, so the
// front wall crosses the hallway and no lane past it is a way on.
TEST(HallwayView, ARoomInLineAcrossACrossingIsNoWayOn) {
  for (const double door : {0.8, 1.0, 1.3}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<laser_features::LineSegment> lines;
    const double wall = 0.775, half = 0.5 * door, mouth = 1.0, front = 2.5;  // the crossing from 1.0 to 2.5 m
    addWall(&pts, &lines, {-6.0, wall}, {mouth, wall});    // the hallway, ending at the crossing
    addWall(&pts, &lines, {-6.0, -wall}, {mouth, -wall});
    addWall(&pts, &lines, {mouth, wall}, {mouth, 8.0});    // the crossing's near walls
    addWall(&pts, &lines, {mouth, -wall}, {mouth, -8.0});
    addWall(&pts, &lines, {front, 8.0}, {front, half});    // its far wall, the room's front wall with the door
    addWall(&pts, &lines, {front, -half}, {front, -8.0});
    addWall(&pts, &lines, {front, wall}, {front + 5.0, wall});  // the room, in line
    addWall(&pts, &lines, {front, -wall}, {front + 5.0, -wall});
    addWall(&pts, &lines, {front + 5.0, -wall}, {front + 5.0, wall});
    const auto v = viewHallway(pts, lines, 0.0, HallwayViewParams());
    EXPECT_NEAR(v.free_ahead, front, 0.05) << door << " m door";
    EXPECT_TRUE(v.wall_across) << door << " m door";
  }
}

// Along an open area's wall (a lobby: free on the other side deeper than the widest hallway) the
// mid-line is the one-wall distance from the wall the robot sees, nearer or farther, so that the
// robot keeps to the wall where the area's doors and hallways are (a wall farther than a hallway's
// walls are, up to the widest hallway, is made for); with the other side a hallway's far wall (up
// to the widest hallway) it only keeps the one-wall distance, as before.
TEST(HallwayView, AlongAnOpenAreasWallTheMidLineKeepsTheOneWallDistance) {
  const HallwayViewParams params;
  for (const double to_wall : {0.6, 1.2, 1.8, 3.0}) {
    for (const int side : {1, -1}) {
      SCOPED_TRACE(std::to_string(to_wall) + " m, side " + std::to_string(side));
      // An open area: its wall on `side`, nothing on the other within 10 m.
      std::vector<Eigen::Vector2d> pts;
      std::vector<laser_features::LineSegment> lines;
      addWall(&pts, &lines, {-6.0, side * to_wall}, {6.0, side * to_wall});
      addWall(&pts, &lines, {-6.0, -side * 10.0}, {6.0, -side * 10.0});
      const auto open = viewHallway(pts, lines, 0.0, params);
      EXPECT_TRUE(open.open_area_beside);
      EXPECT_NEAR(open.centre_offset, side * (to_wall - params.min_wall_clearance), 1e-9);
      if (to_wall > params.wall_max_lateral) continue;
      // A 3.8 m hallway (the widest is 4 m): its far wall is seen in the scan, not as a wall beside.
      std::vector<Eigen::Vector2d> hall_pts;
      std::vector<laser_features::LineSegment> hall_lines;
      addWall(&hall_pts, &hall_lines, {-6.0, side * to_wall}, {6.0, side * to_wall});
      addWall(&hall_pts, &hall_lines, {-6.0, side * (to_wall - 3.8)}, {6.0, side * (to_wall - 3.8)});
      const auto hall = viewHallway(hall_pts, hall_lines, 0.0, params);
      EXPECT_FALSE(hall.open_area_beside);
      if (!hall.left_wall || !hall.right_wall)
        EXPECT_NEAR(hall.centre_offset, side * std::min(0.0, to_wall - params.min_wall_clearance), 1e-9);
    }
  }
}

// A double door is as wide as the narrowest hallway's mouth: the side beside it is a door, not a
// branch, where laser_features sees a door there (a room behind it). A junction's opening, a door
// farther along, on the other side, or across the hallway is not in the mouth.
TEST(HallwayView, ADoubleDoorInTheMouthBesideTheRobotIsNoBranch) {
  const auto opening = [](Eigen::Vector2d centre, double theta, double width, laser_features::OpeningKind kind) {
    laser_features::Opening o;
    const Eigen::Vector2d along(-std::sin(theta), std::cos(theta));
    o.left = centre + 0.5 * width * along;
    o.right = centre - 0.5 * width * along;
    o.center = centre;
    o.theta = theta;
    o.width = width;
    o.kind = kind;
    o.room_behind = kind == laser_features::OpeningKind::kDoor;
    return o;
  };
  using laser_features::OpeningKind;
  const double clearance = 0.35, tol = HallwayViewParams().wall_parallel_tolerance;
  for (const double direction : {0.0, 0.7}) {
    const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
    const auto door = opening(0.1 * u + 1.55 * n, direction + 0.5 * kPi, 1.75, OpeningKind::kDoor);
    EXPECT_TRUE(exploration::doorInMouth({door}, Eigen::Vector2d::Zero(), direction, 1, clearance, 1.4, tol)) << direction;
    EXPECT_FALSE(exploration::doorInMouth({door}, Eigen::Vector2d::Zero(), direction, -1, clearance, 1.4, tol)) << direction;
    const auto branch = opening(0.1 * u + 1.55 * n, direction + 0.5 * kPi, 1.75, OpeningKind::kJunction);
    EXPECT_FALSE(exploration::doorInMouth({branch}, Eigen::Vector2d::Zero(), direction, 1, clearance, 1.4, tol)) << direction;
    const auto farther = opening(2.0 * u + 1.55 * n, direction + 0.5 * kPi, 1.75, OpeningKind::kDoor);
    EXPECT_FALSE(exploration::doorInMouth({farther}, Eigen::Vector2d::Zero(), direction, 1, clearance, 1.4, tol)) << direction;
    const auto ahead = opening(0.5 * u + 1.55 * n, direction, 1.75, OpeningKind::kDoor);
    EXPECT_FALSE(exploration::doorInMouth({ahead}, Eigen::Vector2d::Zero(), direction, 1, clearance, 1.4, tol)) << direction;
    // A single door is no mouth: one found there lies beside it.
    const auto single = opening(0.1 * u + 1.55 * n, direction + 0.5 * kPi, 1.0, OpeningKind::kDoor);
    EXPECT_FALSE(exploration::doorInMouth({single}, Eigen::Vector2d::Zero(), direction, 1, clearance, 1.4, tol)) << direction;
    // Seen from the crossing's expected centre 2 m ahead, the door beside the robot is not there.
    EXPECT_FALSE(exploration::doorInMouth({door}, 2.0 * u, direction, 1, clearance, 1.4, tol)) << direction;
  }
}

// A double door straight ahead (as wide as the narrowest hallway's mouth, so a lane of a mouth's
// width passes through it) is a wall across the hallway where laser_features sees a room behind it:
// the hallway ends at it. A junction's opening there is the way on.
TEST(HallwayView, ADoubleDoorAheadEndsTheHallway) {
  std::vector<Eigen::Vector2d> pts;
  std::vector<laser_features::LineSegment> lines;
  addWall(&pts, &lines, {-6.0, 1.5}, {3.0, 1.5});  // a 3 m hallway, crossed 3 m ahead by a wall with a 1.75 m door
  addWall(&pts, &lines, {-6.0, -1.5}, {3.0, -1.5});
  addWall(&pts, &lines, {3.0, 1.5}, {3.0, 0.875});
  addWall(&pts, &lines, {3.0, -0.875}, {3.0, -1.5});
  const exploration::HallwayView v = viewHallway(pts, lines, 0.0, HallwayViewParams());
  ASSERT_FALSE(v.wall_across);  // a lane of a mouth's width passes through the door
  laser_features::Opening door;
  door.left = {3.0, 0.875};
  door.right = {3.0, -0.875};
  door.center = {3.0, 0.0};
  door.theta = 0.0;
  door.width = 1.75;
  door.kind = laser_features::OpeningKind::kDoor;
  door.room_behind = true;
  const auto across = exploration::doorAcross({door}, v, 0.0, HallwayViewParams(), BuildingRules());
  ASSERT_TRUE(across.has_value());
  EXPECT_NEAR(*across, 3.0, 1e-9);
  exploration::HallwayView ended = v;
  exploration::endWallAt(pts, lines, 0.0, HallwayViewParams(), *across, &ended);
  EXPECT_TRUE(ended.wall_across);
  EXPECT_NEAR(ended.free_ahead, 3.0, 1e-9);
  laser_features::Opening junction = door;
  junction.kind = laser_features::OpeningKind::kJunction;
  EXPECT_FALSE(exploration::doorAcross({junction}, v, 0.0, HallwayViewParams(), BuildingRules()).has_value());
  laser_features::Opening aside = door;  // beside the mid-line, not across it
  aside.left = {3.0, 1.4};
  aside.right = {3.0, 0.3};
  aside.center = {3.0, 0.85};
  EXPECT_FALSE(exploration::doorAcross({aside}, v, 0.0, HallwayViewParams(), BuildingRules()).has_value());
  // The hallway's own mouth, as wide as the hallway between its walls' ends, is no door across it
  // (BuildingRules::fitsInEndWall): a 1.75 m hallway, whose walls end 3 m ahead at a crossing.
  exploration::HallwayView narrow = v;
  narrow.left_lateral = 0.875;
  narrow.right_lateral = -0.875;
  EXPECT_FALSE(exploration::doorAcross({door}, narrow, 0.0, HallwayViewParams(), BuildingRules()).has_value());
}
