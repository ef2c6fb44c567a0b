#include "exploration/oblique_hallways.h"

#include "laser_features/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;

std::vector<double> obliqueWays(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin,
                                double direction, double half_width, double min_free, double max_turn,
                                double off_axis, double step) {
  // Counter-clockwise from -max_turn to +max_turn; a run of free directions is one way.
  std::vector<double> ways;
  const int n = int(std::floor(max_turn / step + 1e-9));
  int run_start = 0, run_length = 0;
  auto close_run = [&]() {
    if (run_length > 0) ways.push_back(normalizeAngle(direction + (run_start + 0.5 * (run_length - 1)) * step));
    run_length = 0;
  };
  for (int k = -n; k <= n; ++k) {
    const double rel = k * step;
    const bool free = offAxis(rel, 0.0) >= off_axis &&
                      corridorFree(points, origin, normalizeAngle(direction + rel), half_width, min_free) >= min_free;
    if (free) {
      if (run_length == 0) run_start = k;
      ++run_length;
    } else {
      close_run();
    }
  }
  close_run();
  std::reverse(ways.begin(), ways.end());  // left first
  return ways;
}

namespace {

// The width of the hallway `w` seen from `inside` (robot frame): between its two walls; with one
// wall seen, from it to the scan's points across (capped at `cap`, m). The wall on the inner side of
// a turn into a hallway at an angle starts at the turn's corner and is seen edge-on from the
// hallway's end: points, too few at that slant for a line.
double widthAcross(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& inside, const HallwayView& w,
                   double clearance, double cap) {
  if (w.left_wall && w.right_wall) return w.width();
  if (!w.left_wall && !w.right_wall) return std::numeric_limits<double>::infinity();
  const double towards = w.wall_direction + (w.left_wall ? -0.5 : 0.5) * kPi;  // the side with no wall seen
  const double wall = w.left_wall ? w.left_lateral : -w.right_lateral;
  return wall + corridorFree(points, inside, towards, clearance, cap + 1.0);
}

// The length-weighted direction (robot frame) of the walls beside `inside` along `way` (as
// viewHallway takes them) that reach abeam of it or beyond and run at an angle to the quarter turns
// of `axis`; none if none does. A wall that ends behind `inside` is a piece of the corner the way
// passes (a mouth cut at a slant), not the hallway's.
std::optional<double> directionAtAngle(const std::vector<laser_features::LineSegment>& lines,
                                       const Eigen::Vector2d& inside, double way, double axis,
                                       const HallwayViewParams& params) {
  const Eigen::Vector2d u(std::cos(way), std::sin(way)), n(-u.y(), u.x());
  double sin_sum = 0.0, cos_sum = 0.0;
  for (laser_features::LineSegment l : lines) {
    l.start -= inside;
    l.end -= inside;
    const std::optional<WallBeside> w = wallBeside(l, way, u, n, params, params.wall_max_lateral);
    if (!w || offAxis(way + w->diff, axis) < params.wall_parallel_tolerance) continue;
    if (std::max(l.start.dot(u), l.end.dot(u)) < 0.0) continue;
    sin_sum += l.length() * std::sin(2.0 * w->diff);
    cos_sum += l.length() * std::cos(2.0 * w->diff);
  }
  if (sin_sum == 0.0 && cos_sum == 0.0) return std::nullopt;
  return normalizeAngle(way + 0.5 * std::atan2(sin_sum, cos_sum));
}

struct WingSight {
  double direction;  // rad, robot frame: its walls'
  bool both_walls;
};

// A hallway at an angle to the quarter turns of `axis` seen from `inside` along `way` (robot frame):
// its walls' direction at an angle (a room's walls seen past a door are not), and its width across
// within `max_width`.
std::optional<WingSight> wingSeenFrom(const std::vector<Eigen::Vector2d>& points,
                                      const std::vector<laser_features::LineSegment>& lines,
                                      const Eigen::Vector2d& inside, double way, double axis,
                                      const HallwayViewParams& params, double max_width) {
  HallwayView w = viewHallwayFrom(points, lines, inside, way, params);
  const bool both = w.left_wall && w.right_wall;
  // One wall seen: its direction is that of its lines at an angle alone (the hallway's own walls at
  // the turn's corner lie within the tolerance of the way too).
  if (w.left_wall != w.right_wall) {
    const std::optional<double> at_angle = directionAtAngle(lines, inside, way, axis, params);
    w.wall_direction_valid = at_angle.has_value();
    w.wall_direction = at_angle.value_or(0.0);
  }
  if (!(w.wall_direction_valid && offAxis(w.wall_direction, axis) >= params.wall_parallel_tolerance &&
        widthAcross(points, inside, w, params.clearance, max_width) <= max_width))
    return std::nullopt;
  return WingSight{w.wall_direction, both};
}

}  // namespace

std::vector<ObliqueWay> obliqueHallways(const std::vector<Eigen::Vector2d>& points,
                                        const std::vector<laser_features::LineSegment>& lines, const HallwayView& view,
                                        double direction, const HallwayViewParams& params, double min_free,
                                        double max_width) {
  // Directions every 5 deg: a 1.5 m hallway's mouth subtends more than twice that from min_free.
  constexpr double kStep = 0.0873;
  // m, origins nearer each other than this along the hallway see the same ways.
  constexpr double kMinOriginStep = 0.1;
  // A wing's mouth need not face the crossing's centre (its wall may start at the corner, beside the
  // hallway's end, or bend at the mouth): the ways are looked for from the centre and from across the
  // crossing, wherever the robot fits (half the hallway's width less the clearance to either side,
  // as far back, and on to the end wall less the clearance, where a wing leaving backwards or through
  // a bent mouth opens).
  const double half = std::max(0.0, (view.width() > 0.0 ? 0.5 * view.width() : 0.5 * params.min_mouth) - params.clearance);
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  const double ahead = view.free_ahead - params.clearance - view.end_centre.dot(u);
  std::vector<double> alongs{0.0, -half};
  if (ahead > kMinOriginStep) alongs.insert(alongs.end(), {0.5 * ahead, ahead});
  std::vector<ObliqueWay> hallways;
  for (const double along : alongs) {
    for (const double lateral : {0.0, half, -half}) {
      const Eigen::Vector2d origin = view.end_centre + along * u + lateral * n;
      const std::vector<double> ways = obliqueWays(points, origin, direction, params.clearance, min_free, 0.75 * kPi,
                                                   params.wall_parallel_tolerance, kStep);
      for (double way : ways) {
        // Seen from half and three quarters of min_free in: walls on both sides at either depth; one
        // wall only where it runs along the way at both (a shorter wall at an angle is a piece of the
        // corner the way passes, a wing's mouth cut at a slant).
        std::optional<double> wing;
        std::vector<double> one_wall;
        for (double depth : {0.5 * min_free, 0.75 * min_free}) {
          const Eigen::Vector2d inside = origin + depth * Eigen::Vector2d(std::cos(way), std::sin(way));
          const std::optional<WingSight> sight = wingSeenFrom(points, lines, inside, way, direction, params, max_width);
          if (sight && sight->both_walls) {
            wing = sight->direction;
            break;
          }
          if (sight) one_wall.push_back(sight->direction);
        }
        if (!wing && one_wall.size() == 2 &&
            std::abs(normalizeAngle(one_wall[0] - one_wall[1])) < params.wall_parallel_tolerance)
          wing = one_wall[1];
        if (!wing) continue;
        // One wing seen from several origins: its walls' direction within the wall tolerance.
        const bool seen = std::any_of(hallways.begin(), hallways.end(), [&](const ObliqueWay& h) {
          return std::abs(normalizeAngle(h.direction - *wing)) < params.wall_parallel_tolerance;
        });
        if (!seen) hallways.push_back({*wing, origin});
      }
    }
  }
  std::sort(hallways.begin(), hallways.end(), [&](const ObliqueWay& a, const ObliqueWay& b) {
    return normalizeAngle(a.direction - direction) > normalizeAngle(b.direction - direction);  // left first
  });
  return hallways;
}

}  // namespace exploration
