#include "exploration/hallway_view.h"

#include "laser_features/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace exploration {

using laser_features::kPi;
using laser_features::normalizeAngle;

namespace {

// The end wall (`v`'s free distance ahead along `direction`, robot frame) runs on into `side` (+1
// left): a wall line across the hallway there, within wall_same_lateral of the end, reaching
// side_open_distance past the mid-line to that side, as a side hallway's far wall does.
bool endWallRunsInto(const std::vector<laser_features::LineSegment>& lines, double direction, const HallwayView& v,
                     int side, const HallwayViewParams& params) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  return std::any_of(lines.begin(), lines.end(), [&](const laser_features::LineSegment& l) {
    const double len = l.length();
    if (len < params.wall_min_length) return false;
    const Eigen::Vector2d d = (l.end - l.start) / len;
    if (std::abs(d.dot(u)) > std::sin(params.wall_parallel_tolerance)) return false;  // across the hallway
    if (std::abs(0.5 * (l.start + l.end).dot(u) - v.free_ahead) > params.wall_same_lateral) return false;
    const double reach = side * std::max(side * l.start.dot(n), side * l.end.dot(n));
    return side * (reach - v.centre_offset) >= params.side_open_distance;
  });
}

// m, the spacing of the lanes freestLane tries: a mouth is found by a corridor this much narrower.
constexpr double kLaneStep = 0.1;
// The lateral offset (m, + left) of the nearest wall beside the robot within `max_lateral`, if any.
std::optional<double> nearestWallBeside(const std::vector<laser_features::LineSegment>& lines, double direction,
                                        const HallwayViewParams& params, double max_lateral) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  std::optional<double> best;
  for (const auto& l : lines) {
    const std::optional<WallBeside> w = wallBeside(l, direction, u, n, params, max_lateral);
    if (w && (!best || std::abs(w->lateral) < std::abs(*best))) best = w->lateral;
  }
  return best;
}

}  // namespace

double offAxis(double heading, double axis) {
  const double rel = normalizeAngle(heading - axis);
  return std::abs(rel - std::round(rel / (0.5 * kPi)) * 0.5 * kPi);
}

std::optional<WallBeside> wallBeside(const laser_features::LineSegment& l, double direction, const Eigen::Vector2d& u,
                                     const Eigen::Vector2d& n, const HallwayViewParams& params, double max_lateral) {
  const double len = l.length();
  if (len < params.wall_min_length) return std::nullopt;
  const Eigen::Vector2d d = (l.end - l.start) / len;
  double diff = normalizeAngle(std::atan2(d.y(), d.x()) - direction);
  if (diff > 0.5 * kPi) diff -= kPi;
  if (diff < -0.5 * kPi) diff += kPi;
  if (std::abs(diff) > params.wall_parallel_tolerance) return std::nullopt;
  const double a0 = l.start.dot(u), a1 = l.end.dot(u);
  if (std::max(a0, a1) < -params.wall_behind || std::min(a0, a1) > params.wall_ahead) return std::nullopt;
  const double lateral = 0.5 * (l.start + l.end).dot(n);
  if (std::abs(lateral) > max_lateral || std::abs(lateral) < params.wall_min_lateral) return std::nullopt;
  return WallBeside{diff, lateral};
}

double freeDistance(const std::vector<Eigen::Vector2d>& points, double bearing, double half_width,
                    double range_cap, const Eigen::Vector2d& origin) {
  double best = range_cap;
  for (const Eigen::Vector2d& q : points) {
    const Eigen::Vector2d p = q - origin;
    const double r = p.norm();
    if (!(r < best)) continue;
    if (std::abs(normalizeAngle(std::atan2(p.y(), p.x()) - bearing)) <= half_width) best = r;
  }
  return best;
}

namespace {

// The walls beside the robot along `direction` (the nearest each side within wall_max_lateral), how
// far they reach ahead, their mean direction and the hallway's centre between them.
void viewSideWalls(const std::vector<laser_features::LineSegment>& lines, double direction,
                   const HallwayViewParams& params, HallwayView* view) {
  HallwayView& v = *view;
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction));
  const Eigen::Vector2d n(-u.y(), u.x());  // left
  double weight = 0.0, sin_sum = 0.0, cos_sum = 0.0;
  for (const auto& l : lines) {
    const std::optional<WallBeside> w = wallBeside(l, direction, u, n, params, params.wall_max_lateral);
    if (!w) continue;
    const double len = l.length(), diff = w->diff, lateral = w->lateral;
    if (lateral > 0.0 && (!v.left_wall || lateral < v.left_lateral)) {
      v.left_wall = true;
      v.left_lateral = lateral;
    }
    if (lateral < 0.0 && (!v.right_wall || lateral > v.right_lateral)) {
      v.right_wall = true;
      v.right_lateral = lateral;
    }
    // Mean of the doubled angles: undirected lines average without the pi ambiguity.
    sin_sum += len * std::sin(2.0 * diff);
    cos_sum += len * std::cos(2.0 * diff);
    weight += len;
  }
  // How far the walls reach ahead: every line along the direction at either wall's lateral offset.
  for (const auto& l : lines) {
    const double len = l.length();
    if (len < params.wall_min_length) continue;
    const Eigen::Vector2d d = (l.end - l.start) / len;
    if (std::abs(d.dot(n)) > std::sin(params.wall_parallel_tolerance)) continue;
    const double lateral = 0.5 * (l.start + l.end).dot(n);
    const double reach = std::max(l.start.dot(u), l.end.dot(u));
    if (v.left_wall && std::abs(lateral - v.left_lateral) < params.wall_same_lateral) v.left_reach = std::max(v.left_reach, reach);
    if (v.right_wall && std::abs(lateral - v.right_lateral) < params.wall_same_lateral)
      v.right_reach = std::max(v.right_reach, reach);
  }
  if (weight > 0.0) {
    v.wall_direction = normalizeAngle(direction + 0.5 * std::atan2(sin_sum, cos_sum));
    v.wall_direction_valid = true;
  }
  if (v.left_wall && v.right_wall) {
    v.centre_offset = 0.5 * (v.left_lateral + v.right_lateral);
  } else if (v.left_wall) {
    v.centre_offset = std::min(0.0, v.left_lateral - params.min_wall_clearance);
  } else if (v.right_wall) {
    v.centre_offset = std::max(0.0, v.right_lateral + params.min_wall_clearance);
  }
}

void keepToOpenAreaWall(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
                        double direction, const HallwayViewParams& params, HallwayView* view) {
  HallwayView& v = *view;
  // Along an open area's wall (a lobby, a hall, a hallway open on one side to either): the doors and
  // the hallways leaving the area are along its walls, and from its middle the robot sees none of
  // them. The robot keeps to the wall it sees as to a hallway's (the one-wall distance) rather than
  // crossing the area; at the area's corners the open side is the turn. With no wall within
  // wall_max_lateral, the nearest within the widest hallway is the one it makes for.
  std::optional<double> wall;
  if (v.left_wall != v.right_wall) wall = v.left_wall ? v.left_lateral : v.right_lateral;
  if (!v.left_wall && !v.right_wall) wall = nearestWallBeside(lines, direction, params, params.widest_hallway);
  if (wall && openAreaBeside(points, Eigen::Vector2d::Zero(), direction, *wall > 0.0 ? -1 : 1, params.clearance,
                             params.widest_hallway, params.widest_hallway)) {
    v.centre_offset = *wall > 0.0 ? *wall - params.min_wall_clearance : *wall + params.min_wall_clearance;
    v.open_area_beside = true;
  }
}

// How far ahead a lane as wide as the narrowest hallway's mouth is free (the freest lane tried; -1
// where none is tried).
double hallwayFreeAhead(const std::vector<Eigen::Vector2d>& points, double direction, const HallwayViewParams& params,
                        double range_cap, const HallwayView& v) {
  const Eigen::Vector2d n(-std::sin(direction), std::cos(direction));  // left
  // A hallway goes on only through a mouth as wide as the narrowest hallway's. Where no lane is free
  // that wide, either an obstacle stands in it (a pillar, furniture: the hallway's walls run on
  // beside it unbroken) or a wall crosses it: its end wall, with a door in it or not, or a room's
  // front wall across a crossing (that room's walls may line up with the hallway's beyond it). The
  // sector ahead alone sees through a door on the mid-line once nearer than the door's width over
  // its tangent (3 m for a 1 m door), and the robot fits through the door.
  // Lanes between the walls seen, and up to half the widest hallway to a side with none (at a
  // crossing, in a wing's mouth: where the hallway ahead lies is not known). A wall across lies
  // ahead of the robot, past its own clearance (a corner beside it is none).
  const double mouth_half = 0.5 * (params.min_mouth - kLaneStep);
  double hallway_free = -1.0;
  const double lo = v.right_wall ? v.right_lateral + mouth_half : mouth_half - params.wall_max_lateral;
  const double hi = v.left_wall ? v.left_lateral - mouth_half : params.wall_max_lateral - mouth_half;
  // From the middle lane outwards, stopping at the first as free as the sector ahead (then nothing
  // is clipped): in a hallway the first lane tried is that one.
  // Reused between calls: no allocation per scan once it has grown to the most lanes.
  thread_local std::vector<double> laterals;
  laterals.clear();
  for (double lateral = lo; lateral <= hi + 1e-9; lateral += kLaneStep) laterals.push_back(lateral);
  const int lanes = int(laterals.size()), mid = lanes / 2;
  for (int k = 0; k < 2 * lanes && hallway_free < v.free_ahead; ++k) {
    const int i = mid + ((k % 2) ? (k + 1) / 2 : -(k / 2));
    if (i < 0 || i >= lanes) continue;
    hallway_free = std::max(hallway_free, corridorFree(points, laterals[i] * n, direction, mouth_half, range_cap));
  }
  return hallway_free;
}

}  // namespace

HallwayView viewHallway(const std::vector<Eigen::Vector2d>& points,
                        const std::vector<laser_features::LineSegment>& lines, double direction,
                        const HallwayViewParams& params, double range_cap) {
  HallwayView v;
  v.free_ahead = freeDistance(points, direction, params.ahead_sector, range_cap);
  // A side is open where a hallway's mouth is, and only there: a door lets a side sector see into
  // the room behind it whenever it is wider than the sector's chord at the wall (a 1.2 m door at
  // 0.75 m, in a 1.5 m hallway, subtends 77 deg), but no door is as wide as the narrowest hallway.
  const auto open = [&](const Eigen::Vector2d& origin, int side) {
    return mouthBeside(points, origin, direction, side, params.clearance, params.min_mouth, params.side_open_distance);
  };
  v.open_left = open(Eigen::Vector2d::Zero(), 1);
  v.open_right = open(Eigen::Vector2d::Zero(), -1);

  viewSideWalls(lines, direction, params, &v);
  keepToOpenAreaWall(points, lines, direction, params, &v);
  const double hallway_free = hallwayFreeAhead(points, direction, params, range_cap, v);
  if (hallway_free > params.clearance && hallway_free < v.free_ahead &&
      !wallsSpan(points, lines, v, direction, hallway_free - params.clearance, hallway_free + params.clearance, params)) {
    endWallAt(points, lines, direction, params, hallway_free, &v);
    return v;
  }
  seeEnd(points, lines, direction, params, &v);
  return v;
}

void seeEnd(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
            double direction, const HallwayViewParams& params, HallwayView* v) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  const double half_width = v->left_wall && v->right_wall ? 0.5 * v->width() : 1.0;
  const Eigen::Vector2d centre = std::max(0.0, v->free_ahead - half_width) * u + v->centre_offset * n;
  v->end_centre = centre;
  // A side hallway as wide as this one or wider opens about the crossing's centre. A narrower one
  // (hallways are 1.5-4.0 m wide, and either may be the narrower) has its far wall in line with the
  // end wall, as at an L or T corner, and its mouth lies between that centre and the end wall:
  // where the end wall runs on into the side, the mouth is looked for up to it, as near as the
  // robot's corridor fits. (A wing at an angle leaves the end wall's line; obliqueHallways finds it.)
  const double nearest_end = std::max(0.0, v->free_ahead - params.clearance);
  const auto open = [&](int side, Eigen::Vector2d* mouth) {
    *mouth = centre;
    const double last = endWallRunsInto(lines, direction, *v, side, params) ? nearest_end : centre.dot(u);
    for (double along = centre.dot(u); along <= last + 1e-9; along += kLaneStep) {
      const Eigen::Vector2d origin = along * u + v->centre_offset * n;
      if (mouthBeside(points, origin, direction, side, params.clearance, params.min_mouth, params.side_open_distance)) {
        *mouth = origin;
        return true;
      }
    }
    return false;
  };
  v->end_open_left = open(1, &v->end_mouth_left);
  v->end_open_right = open(-1, &v->end_mouth_right);
}

void endWallAt(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
               double direction, const HallwayViewParams& params, double distance, HallwayView* v) {
  v->free_ahead = distance;
  v->wall_across = true;
  seeEnd(points, lines, direction, params, v);
}

bool mouthWideDoor(const laser_features::Opening& o, double min_mouth) {
  return o.kind == laser_features::OpeningKind::kDoor && o.width >= min_mouth;
}

std::optional<double> doorAcross(const std::vector<laser_features::Opening>& openings, const HallwayView& v,
                                 double direction, const HallwayViewParams& params,
                                 const laser_features::BuildingRules& rules) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  std::optional<double> nearest;
  for (const laser_features::Opening& o : openings) {
    if (!mouthWideDoor(o, params.min_mouth)) continue;
    if (std::abs(normalizeAngle(o.theta - direction)) > params.wall_parallel_tolerance) continue;
    if (v.left_wall && v.right_wall && !rules.fitsInEndWall(o.width, v.width())) continue;
    const double along = o.center.dot(u);
    if (along <= params.clearance || along >= v.free_ahead || (nearest && along >= *nearest)) continue;
    const double a = o.left.dot(n), b = o.right.dot(n);
    if (std::min(a, b) > v.centre_offset || std::max(a, b) < v.centre_offset) continue;
    nearest = along;
  }
  return nearest;
}

namespace {
// m, a surface reaching out this far from a wall's line into the hallway is no part of that wall:
// above the scatter of a wall's points about its line (a building laser's range noise, 1-3 cm) and
// below the shortest stretch of wall beside a door in an end wall (the narrowest hallway less the
// widest single door, 1.5 - 1.2 m).
constexpr double kCornerDepth = 0.1;

// A corner in a wall's gap from `gap_begin` to `gap_end` m along `u`: scan points within it that
// stand out from the line `wall` (the wall's last line before the gap) into the hallway (the
// robot's side) by kCornerDepth to `depth`: a wall across (an end wall, a crossing's near wall)
// meets the hallway's wall there. A door in a side wall has none: its jambs lie in the wall.
bool cornerInGap(const std::vector<Eigen::Vector2d>& points, const laser_features::LineSegment& wall,
                 const Eigen::Vector2d& u, double gap_begin, double gap_end, double depth) {
  const Eigen::Vector2d d = (wall.end - wall.start).normalized();
  Eigen::Vector2d inward(-d.y(), d.x());
  if (inward.dot(-wall.start) < 0.0) inward = -inward;  // towards the robot (the origin)
  for (const Eigen::Vector2d& q : points) {
    const double along = q.dot(u);
    if (along < gap_begin - kCornerDepth || along > gap_end + kCornerDepth) continue;
    const double out = (q - wall.start).dot(inward);
    if (out > kCornerDepth && out < depth) return true;
  }
  return false;
}
}  // namespace

bool wallsSpan(const std::vector<Eigen::Vector2d>& points, const std::vector<laser_features::LineSegment>& lines,
               const HallwayView& view, double direction, double from, double to, const HallwayViewParams& params) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction)), n(-u.y(), u.x());
  // Each wall's stretches along the direction, joined across the gaps of doors: narrower than a
  // hallway's mouth, and no wall across meeting the wall in the gap.
  struct Stretch {
    double begin, end;
    const laser_features::LineSegment* line;
    bool operator<(const Stretch& o) const { return begin < o.begin; }
  };
  const auto spans = [&](bool present, double wall_lateral) {
    if (!present) return false;
    thread_local std::vector<Stretch> stretches;
    stretches.clear();
    for (const auto& l : lines) {
      const double len = l.length();
      if (len <= 0.0 || std::abs((l.end - l.start).dot(n)) / len > std::sin(params.wall_parallel_tolerance)) continue;
      if (std::abs(0.5 * (l.start + l.end).dot(n) - wall_lateral) >= params.wall_same_lateral) continue;
      const double a0 = l.start.dot(u), a1 = l.end.dot(u);
      stretches.push_back({std::min(a0, a1), std::max(a0, a1), &l});
    }
    std::sort(stretches.begin(), stretches.end());
    double begin = 0.0, end = -1e9;
    const laser_features::LineSegment* last = nullptr;  // the line reaching farthest so far
    for (const Stretch& s : stretches) {
      const bool broken = !last || (s.begin > end && (s.begin - end >= params.min_mouth ||
                                                      cornerInGap(points, *last, u, end, s.begin, params.clearance)));
      if (broken) begin = s.begin;  // a mouth or a wall across breaks the wall: a new run starts
      if (!last || s.end > end) {
        end = s.end;
        last = s.line;
      }
      if (begin <= from && end >= to) return true;
    }
    return false;
  };
  return spans(view.left_wall, view.left_lateral) || spans(view.right_wall, view.right_lateral);
}

HallwayView viewHallwayFrom(const std::vector<Eigen::Vector2d>& points,
                            const std::vector<laser_features::LineSegment>& lines, const Eigen::Vector2d& origin,
                            double direction, const HallwayViewParams& params, double range_cap) {
  std::vector<Eigen::Vector2d> shifted_points;
  shifted_points.reserve(points.size());
  for (const Eigen::Vector2d& q : points) shifted_points.push_back(q - origin);
  std::vector<laser_features::LineSegment> shifted_lines = lines;
  for (laser_features::LineSegment& l : shifted_lines) {
    l.start -= origin;
    l.end -= origin;
  }
  return viewHallway(shifted_points, shifted_lines, direction, params, range_cap);
}

Lane freestLane(const std::vector<Eigen::Vector2d>& points, double direction, const HallwayView& view,
                double clearance, double range_cap) {
  const Eigen::Vector2d n(-std::sin(direction), std::cos(direction));
  const double lo = view.right_wall ? view.right_lateral + clearance : view.centre_offset;
  const double hi = view.left_wall ? view.left_lateral - clearance : view.centre_offset;
  Lane best{view.centre_offset, -1.0};
  for (double lateral = lo; lateral <= hi + 1e-9; lateral += kLaneStep) {
    const double free = corridorFree(points, lateral * n, direction, clearance, range_cap);
    const bool nearer = std::abs(lateral - view.centre_offset) < std::abs(best.lateral - view.centre_offset);
    if (free > best.free + 1e-6 || (std::abs(free - best.free) <= 1e-6 && nearer)) best = {lateral, free};
  }
  return best;
}

double corridorFree(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double bearing,
                    double half_width, double range_cap) {
  const Eigen::Vector2d u(std::cos(bearing), std::sin(bearing)), n(-u.y(), u.x());
  double free = range_cap;
  for (const Eigen::Vector2d& q : points) {
    const Eigen::Vector2d p = q - origin;
    const double along = p.dot(u);
    if (along > 0.0 && along < free && std::abs(p.dot(n)) <= half_width) free = along;
  }
  return free;
}

namespace {

// How far along `direction` (both ways from `origin`, m) the robot's corridor straight to `side` is
// free for `depth`: the free stretch of corridor positions, up to `need` (0 where `origin`'s is not).
double freeStretchBeside(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double direction,
                         int side, double clearance, double depth, double need) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction));
  const double bearing = direction + (side >= 0 ? 0.5 : -0.5) * kPi;
  const auto free = [&](double along) { return corridorFree(points, origin + along * u, bearing, clearance, depth) >= depth; };
  if (!free(0.0)) return 0.0;
  constexpr double kStep = 0.05;  // m
  double ahead = 0.0, behind = 0.0;
  while (ahead + behind < need && free(ahead + kStep)) ahead += kStep;
  while (ahead + behind < need && free(-behind - kStep)) behind += kStep;
  return ahead + behind;
}

}  // namespace

bool mouthBeside(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double direction, int side,
                 double clearance, double min_mouth, double depth) {
  const double need = min_mouth - 2.0 * clearance;  // the free stretch of corridor positions
  return freeStretchBeside(points, origin, direction, side, clearance, depth, need) >= need - 1e-9;
}

bool doorInMouth(const std::vector<laser_features::Opening>& openings, const Eigen::Vector2d& origin, double direction,
                 int side, double clearance, double min_mouth, double side_angle) {
  const Eigen::Vector2d u(std::cos(direction), std::sin(direction));
  const double towards = direction + (side >= 0 ? 0.5 : -0.5) * kPi;
  const Eigen::Vector2d n(std::cos(towards), std::sin(towards));
  return std::any_of(openings.begin(), openings.end(), [&](const laser_features::Opening& o) {
    if (!mouthWideDoor(o, min_mouth)) return false;
    const Eigen::Vector2d c = o.center - origin;
    if (c.dot(n) <= 0.0 || std::abs(normalizeAngle(o.theta - towards)) > side_angle) return false;
    const double a = (o.left - origin).dot(u), b = (o.right - origin).dot(u);
    return std::min(a, b) <= -clearance && std::max(a, b) >= clearance;
  });
}

bool openAreaBeside(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin, double direction,
                    int side, double clearance, double widest_hallway, double depth) {
  const double need = widest_hallway - 2.0 * clearance;
  return freeStretchBeside(points, origin, direction, side, clearance, depth, need + 0.05) > need;
}

}  // namespace exploration
