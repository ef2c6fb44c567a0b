// The hallway seen in a scan: free distances, open sides, walls and the mid-line.
#include <gtest/gtest.h>

#include <cmath>

#include "exploration/hallway_view.h"

using exploration::HallwayViewParams;
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
  EXPECT_LT(v.free_left, 1.3);
  (void)kPi;
}
