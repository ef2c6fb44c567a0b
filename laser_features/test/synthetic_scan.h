// Analytic scans for the tests and the benchmark: walls are segments, a beam's range is the nearest
// wall along its ray, plus Gaussian range noise. Header-only, Eigen + std.
#pragma once

#include "laser_features/geometry.h"
#include "laser_features/scan.h"

#include <Eigen/Core>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace laser_features {
namespace synthetic {

struct Wall {
  Eigen::Vector2d a;
  Eigen::Vector2d b;
};

struct World {
  std::vector<Wall> walls;

  void addWall(double ax, double ay, double bx, double by) { walls.push_back({{ax, ay}, {bx, by}}); }
  /// A closed polygon of walls through the given corners.
  void addPolygon(const std::vector<Eigen::Vector2d>& corners) {
    for (size_t i = 0; i < corners.size(); ++i) walls.push_back({corners[i], corners[(i + 1) % corners.size()]});
  }
  /// An axis-aligned box (furniture, a pillar).
  void addBox(double cx, double cy, double sx, double sy) {
    addPolygon({{cx - sx / 2, cy - sy / 2}, {cx + sx / 2, cy - sy / 2}, {cx + sx / 2, cy + sy / 2},
                {cx - sx / 2, cy + sy / 2}});
  }
};

/// Beam layout of a scanner.
struct ScanSpec {
  double angle_min = -kPi;
  double angle_increment = kTwoPi / 720.0;
  size_t beams = 720;
  double range_min = 0.1;
  double range_max = 15.0;

  static ScanSpec full(size_t beams, double angle_min = -kPi) {
    ScanSpec spec;
    spec.angle_min = angle_min;
    spec.angle_increment = kTwoPi / double(beams);
    spec.beams = beams;
    return spec;
  }
  /// A 180 degree scanner; `clockwise` scans from +90 to -90 degrees with a negative increment.
  static ScanSpec half(size_t beams, bool clockwise) {
    ScanSpec spec;
    spec.beams = beams;
    const double step = kPi / double(beams - 1);
    spec.angle_min = clockwise ? 0.5 * kPi : -0.5 * kPi;
    spec.angle_increment = clockwise ? -step : step;
    return spec;
  }
};

/// Distance along the ray from `origin` in direction `direction` (unit) to the wall, or +inf.
inline double rayHitsWall(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction, const Wall& wall) {
  const Eigen::Vector2d edge = wall.b - wall.a;
  const double denominator = cross2(direction, edge);
  if (std::abs(denominator) < 1e-12) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d to_a = wall.a - origin;
  const double t = cross2(to_a, edge) / denominator;
  const double s = cross2(to_a, direction) / denominator;
  if (t <= 0.0 || s < 0.0 || s > 1.0) return std::numeric_limits<double>::infinity();
  return t;
}

/// Exact range of every beam from the sensor pose (in the world), +inf beyond range_max. With
/// `bearing_errors`, beam i is cast at its nominal bearing plus bearing_errors[i].
inline std::vector<double> trueRanges(const World& world, const Pose2D& sensor, const ScanSpec& spec,
                                      const std::vector<double>* bearing_errors = nullptr) {
  std::vector<double> ranges(spec.beams);
  for (size_t i = 0; i < spec.beams; ++i) {
    const double error = bearing_errors ? (*bearing_errors)[i] : 0.0;
    const Eigen::Vector2d direction =
        unitVector(sensor.theta + spec.angle_min + double(i) * spec.angle_increment + error);
    double nearest = std::numeric_limits<double>::infinity();
    for (const Wall& wall : world.walls) nearest = std::min(nearest, rayHitsWall(sensor.translation(), direction, wall));
    ranges[i] = nearest;
  }
  return ranges;
}

/// Ranges with Gaussian range noise of `sigma` (m) and, when `bearing_sigma` (rad) > 0, beams cast
/// at bearings off by Gaussian noise (reported at their nominal bearing); no return (+inf) beyond
/// range_max.
inline std::vector<float> simulateScan(const World& world, const Pose2D& sensor, const ScanSpec& spec,
                                       double sigma, std::mt19937* rng, double bearing_sigma = 0.0) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> bearing_errors(spec.beams, 0.0);
  if (bearing_sigma > 0.0) {
    std::normal_distribution<double> bearing_noise(0.0, bearing_sigma);
    for (double& error : bearing_errors) error = bearing_noise(*rng);
  }
  const std::vector<double> exact = trueRanges(world, sensor, spec, &bearing_errors);
  std::vector<float> ranges(spec.beams);
  for (size_t i = 0; i < spec.beams; ++i) {
    const double range = exact[i] + (sigma > 0.0 ? noise(*rng) : 0.0);
    ranges[i] = exact[i] > spec.range_max ? std::numeric_limits<float>::infinity() : float(range);
  }
  return ranges;
}

inline ScanView makeView(const ScanSpec& spec, const std::vector<float>& ranges) {
  ScanView view;
  view.angle_min = spec.angle_min;
  view.angle_increment = spec.angle_increment;
  view.range_min = spec.range_min;
  view.range_max = spec.range_max;
  view.ranges = ranges.data();
  view.size = ranges.size();
  return view;
}

/// The infinite line of a wall as the sensor sees it.
inline Line wallInSensorFrame(const Wall& wall, const Pose2D& sensor) {
  return transformLineToFrame(lineThroughPoints(wall.a, wall.b), sensor);
}

/// A point given in the world, in the sensor frame.
inline Eigen::Vector2d pointInSensorFrame(const Eigen::Vector2d& p, const Pose2D& sensor) {
  return transformPoint(inverse(sensor), p);
}

// --- Scenes -------------------------------------------------------------------------------------

/// A closed rectangular room [0, w] x [0, h].
inline World rectangularRoom(double w, double h) {
  World world;
  world.addPolygon({{0, 0}, {w, 0}, {w, h}, {0, h}});
  return world;
}

/// A hallway along x, y in [0, 2], from x = 0 to x = 30 (closed ends), with a door of `door_width`
/// in its upper wall centred at x = door_x, leading into a 4 m x 4 m room above.
inline World hallwayWithSideDoor(double door_x, double door_width) {
  World world;
  const double half = door_width / 2;
  world.addWall(0, 0, 30, 0);                        // lower wall
  world.addWall(0, 2, door_x - half, 2);             // upper wall, left of the door
  world.addWall(door_x + half, 2, 30, 2);            // upper wall, right of the door
  world.addWall(0, 0, 0, 2);                         // ends
  world.addWall(30, 0, 30, 2);
  world.addWall(door_x - 2, 2, door_x - 2, 6);       // the room behind the door
  world.addWall(door_x + 2, 2, door_x + 2, 6);
  world.addWall(door_x - 2, 6, door_x + 2, 6);
  return world;
}

/// A room [0, 6] x [0, 5] with a door of `door_width` in its right wall (x = 6) centred at y = door_y,
/// leading into a hallway along y behind it (x in [6, 8]).
inline World roomWithDoor(double door_y, double door_width) {
  World world;
  const double half = door_width / 2;
  world.addWall(0, 0, 6, 0);
  world.addWall(0, 5, 6, 5);
  world.addWall(0, 0, 0, 5);
  world.addWall(6, 0, 6, door_y - half);
  world.addWall(6, door_y + half, 6, 5);
  world.addWall(8, -10, 8, 15);  // far wall of the hallway
  world.addWall(6, 0, 6, -10);   // hallway continues; its near wall
  world.addWall(6, 5, 6, 15);
  return world;
}

/// An office-like scene for the benchmark: a 7 m x 5 m room with two doors into a hallway, a desk,
/// a cabinet and a pillar.
inline World officeScene() {
  World world;
  world.addWall(0, 0, 7, 0);
  world.addWall(0, 0, 0, 5);
  world.addWall(7, 0, 7, 1.0);   // right wall with a door at y in [1.0, 1.9]
  world.addWall(7, 1.9, 7, 5);
  world.addWall(0, 5, 3.0, 5);   // top wall with a door at x in [3.0, 3.9]
  world.addWall(3.9, 5, 7, 5);
  world.addWall(0, 7, 12, 7);    // hallway above, x in [0, 12], y in [5, 7]
  world.addWall(7, 5, 12, 5);
  world.addWall(9, 0, 9, 5);     // the room to the right
  world.addWall(7, 0, 9, 0);
  world.addBox(1.2, 3.8, 1.6, 0.8);  // desk
  world.addBox(5.5, 0.4, 1.0, 0.5);  // cabinet
  world.addBox(4.5, 3.0, 0.3, 0.3);  // pillar
  return world;
}

}  // namespace synthetic
}  // namespace laser_features
