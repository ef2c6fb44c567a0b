#include "laser_features/opening_extractor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace laser_features {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// m, farther than this from the last hit, the next beam meets the wall line at grazing incidence and
// says little about where the wall ends.
constexpr double kMaxEdgeRefinement = 0.25;

/// The neighbour of beam i in `direction` (+1 counter-clockwise, -1 clockwise), or size() past the
/// end of a scan that is not circular.
size_t stepBeam(const ScanPoints& points, size_t i, int direction) {
  const size_t n = points.size();
  if (direction > 0) {
    if (i + 1 < n) return i + 1;
    return points.circular() ? 0 : n;
  }
  if (i > 0) return i - 1;
  return points.circular() ? n - 1 : n;
}

}  // namespace

OpeningExtractor::OpeningExtractor(const Params& params) : params_(params) { reserve(1024); }

void OpeningExtractor::reserve(size_t beams) { beam_line_.reserve(beams); }

double OpeningExtractor::minWidth() const {
  return std::max(params_.rules.door_min_width, 2.0 * params_.robot_radius);
}

void OpeningExtractor::labelBeams(const ScanPoints& points, const std::vector<LineSegment>& lines) {
  beam_line_.assign(points.size(), -1);
  for (size_t id = 0; id < lines.size(); ++id) {
    size_t beam = lines[id].first_beam;
    for (size_t steps = 0; steps < points.size(); ++steps) {
      beam_line_[beam] = int32_t(id);
      if (beam == lines[id].last_beam) break;
      beam = stepBeam(points, beam, +1);
      if (beam >= points.size()) break;
    }
  }
}

// The end of a wall lies between its last hit and the next beam, which passed the wall line; the
// midpoint of the two is an unbiased estimate of the edge (the last hit alone is biased inwards by
// half a beam spacing on average).
Eigen::Vector2d OpeningExtractor::segmentEdge(const ScanPoints& points, const LineSegment& segment,
                                              bool at_end) const {
  const Eigen::Vector2d& last_hit = at_end ? segment.end : segment.start;
  const size_t neighbour = stepBeam(points, at_end ? segment.last_beam : segment.first_beam, at_end ? +1 : -1);
  if (neighbour >= points.size()) return last_hit;
  const double range_to_wall = rangeToLine(segment.line, points.bearing(neighbour));
  if (!std::isfinite(range_to_wall)) return last_hit;
  const BeamPoint& beam = points[neighbour];
  const bool passed_wall = beam.status == BeamStatus::kNoReturn ||
                           (beam.status == BeamStatus::kValid &&
                            beam.range > range_to_wall + params_.line_tolerance);
  if (!passed_wall) return last_hit;
  const Eigen::Vector2d missed = range_to_wall * points.unit(neighbour);
  if ((missed - last_hit).norm() > kMaxEdgeRefinement) return last_hit;
  return 0.5 * (last_hit + missed);
}

Eigen::Vector2d OpeningExtractor::beamEdge(const ScanPoints& points, const std::vector<LineSegment>& lines,
                                           size_t beam, int outward) const {
  const int32_t id = beam_line_[beam];
  if (id >= 0) {
    const LineSegment& segment = lines[size_t(id)];
    if (outward > 0 && beam == segment.last_beam) return segmentEdge(points, segment, true);
    if (outward < 0 && beam == segment.first_beam) return segmentEdge(points, segment, false);
  }
  return points[beam].p;
}

// True when the surface at `beam` ends towards `towards`: the next informative beam that way returns
// nothing or is at least jump_min farther, or the beam ends a line segment on that side.
bool OpeningExtractor::isJumpEdge(const ScanPoints& points, size_t beam, int towards) const {
  const int32_t id = beam_line_[beam];
  const size_t neighbour = stepBeam(points, beam, towards);
  if (id >= 0 && neighbour < points.size() && beam_line_[neighbour] != id) return true;
  size_t next = beam;
  for (int tries = 0; tries < 3; ++tries) {
    next = stepBeam(points, next, towards);
    if (next >= points.size()) return false;
    const BeamPoint& next_point = points[next];
    if (next_point.status == BeamStatus::kNoReturn) return true;
    if (next_point.status == BeamStatus::kValid) return next_point.range - points[beam].range >= params_.jump_min;
  }
  return false;
}

// Classifies the beams strictly between the bearings of the two edges against the opening line:
// through (behind the line, or no return), on the line (a wall continues: no gap), in front (an
// occluder: the gap is not seen). The passage is clear when at least half of the beams go through,
// at most a few touch the line (jamb faces), and the free space reaches minDepth() behind the line.
OpeningExtractor::Passage OpeningExtractor::checkPassage(const ScanPoints& points,
                                                         const Eigen::Vector2d& edge_a,
                                                         const Eigen::Vector2d& edge_b,
                                                         const Line& opening_line) const {
  Passage passage;
  const double bearing_a = std::atan2(edge_a.y(), edge_a.x());
  const double bearing_b = std::atan2(edge_b.y(), edge_b.x());
  const double delta = normalizeAngle(bearing_b - bearing_a);
  const double low = delta >= 0.0 ? bearing_a : bearing_b;
  const double span = std::abs(delta);
  const double step = points.increment();
  size_t beam = points.indexOfBearing(low);
  if (beam >= points.size()) beam = points.indexOfBearing(low + step);
  if (beam >= points.size()) return passage;

  const HesseLine line(opening_line);
  // Room behind (BuildingRules): a point seen through the opening that lies beyond an edge by more
  // than a hallway's walls could run from the mouth at that depth, plus the edges' error.
  const double width = (edge_b - edge_a).norm();
  const Eigen::Vector2d along = (edge_b - edge_a) / std::max(width, 1e-9);
  const double spread = params_.rules.branchSpread();
  const double edge_error = params_.rules.width_tolerance + params_.line_tolerance;
  int beyond = 0;
  int through = 0, on_line = 0, in_front = 0;
  const size_t max_steps = size_t(span / step) + 2;
  double offset = normalizeAngle(points.bearing(beam) - low);  // of `beam` from the first edge
  for (size_t k = 0; k <= max_steps && beam < points.size();
       ++k, beam = stepBeam(points, beam, +1), offset += step) {
    if (offset <= 0.25 * step) continue;           // the first edge's own beam
    if (offset >= span - 0.25 * step) break;       // the second edge's own beam and beyond
    const BeamPoint& point = points[beam];
    if (point.status == BeamStatus::kNoReturn) {
      ++through;
      passage.depth = kInfinity;
    } else if (point.status == BeamStatus::kValid) {
      const double depth = line.distance(point.p);
      if (depth < -params_.line_tolerance) {
        ++in_front;
      } else if (depth <= params_.line_tolerance) {
        ++on_line;
      } else {
        ++through;
        passage.depth = std::max(passage.depth, depth);
        const double s = (point.p - edge_a).dot(along);
        if (std::max(-s, s - width) > edge_error + spread * depth) ++beyond;
      }
    }
  }
  const int total = through + on_line + in_front;
  passage.clear = through >= 1 && 2 * through >= total && on_line <= std::max(2, total / 10) &&
                  passage.depth >= minDepth();
  passage.room_behind = beyond >= kRoomBeams;
  return passage;
}

bool OpeningExtractor::makeOpening(const ScanPoints& points, const Eigen::Vector2d& edge_a,
                                   const Eigen::Vector2d& edge_b, OpeningSource source, double support,
                                   Opening* opening) const {
  const double width = (edge_a - edge_b).norm();
  if (!(width >= minWidth() && width <= maxWidth())) return false;
  const Line opening_line = lineThroughPoints(edge_a, edge_b);
  // With the sensor on (or next to) the opening line we cannot tell which side is beyond it.
  if (!(opening_line.r >= params_.min_line_distance)) return false;
  const Passage passage = checkPassage(points, edge_a, edge_b, opening_line);
  if (!passage.clear) return false;

  opening->theta = opening_line.alpha;  // the canonical normal points away from the sensor
  opening->center = 0.5 * (edge_a + edge_b);
  const bool a_is_left = opening_line.direction().dot(edge_a - opening->center) > 0.0;
  opening->left = a_is_left ? edge_a : edge_b;
  opening->right = a_is_left ? edge_b : edge_a;
  opening->width = width;
  opening->room_behind = passage.room_behind;
  opening->kind = params_.rules.isDoor(width, passage.room_behind) ? OpeningKind::kDoor : OpeningKind::kJunction;
  opening->source = source;
  const double depth_score = std::min(1.0, passage.depth / (2.0 * minDepth()));
  opening->confidence = std::clamp(depth_score * support, 0.0, 1.0);
  return opening->center.allFinite() && opening->left.allFinite() && opening->right.allFinite() &&
         std::isfinite(opening->theta);
}

void OpeningExtractor::addIfNew(const Opening& opening, std::vector<Opening>* openings) const {
  for (const Opening& known : *openings) {
    const double same_distance =
        std::max(params_.duplicate_distance, 0.5 * std::min(known.width, opening.width));
    if ((known.center - opening.center).norm() < same_distance) return;
  }
  openings->push_back(opening);
}

// (b) Two pieces of one wall with a gap of door or junction width between them.
void OpeningExtractor::findCollinearGaps(const ScanPoints& points, const std::vector<LineSegment>& lines,
                                         std::vector<Opening>* openings) const {
  Opening opening;
  for (size_t i = 0; i < lines.size(); ++i) {
    const LineSegment& a = lines[i];
    if (a.line.r < params_.min_line_distance) continue;
    const Eigen::Vector2d t = a.line.direction();  // start -> end is counter-clockwise: increasing t
    for (size_t j = 0; j < lines.size(); ++j) {
      if (j == i) continue;
      const LineSegment& b = lines[j];
      // Take each pair once, with a before b along the wall.
      if (!(t.dot(a.end) < t.dot(b.start))) continue;
      const Eigen::Vector2d difference = lineDifference(a.line, b.line);
      const bool collinear = lineMahalanobisSq(a.line, b.line) <= params_.collinear_chi2 ||
                             (std::abs(difference.x()) <= params_.collinear_angle &&
                              std::abs(difference.y()) <= params_.collinear_distance);
      if (!collinear || std::abs(difference.x()) > 0.5 * kPi) continue;
      const Eigen::Vector2d edge_a = segmentEdge(points, a, true);
      const Eigen::Vector2d edge_b = segmentEdge(points, b, false);
      const double support = 0.5 + 0.25 * (std::min(1.0, a.length()) + std::min(1.0, b.length()));
      if (makeOpening(points, edge_a, edge_b, OpeningSource::kCollinearGap, support, &opening))
        addIfNew(opening, openings);
    }
  }
}

// (c) In a hallway: two pieces of the same side wall, parallel to the hallway axis and at most
// hallway_step_max_offset apart laterally, with a gap between them along the axis (a side branch
// or a recessed door: a large step of the lateral distance, perpendicular to the hallway).
void OpeningExtractor::findHallwaySteps(const ScanPoints& points, const std::vector<LineSegment>& lines,
                                        const PlaceEstimate& place, std::vector<Opening>* openings) const {
  if (place.type != PlaceType::kHallway) return;
  const Eigen::Vector2d along = unitVector(place.axis);
  const Eigen::Vector2d across(-along.y(), along.x());
  Line axis_line;  // any line parallel to the axis
  axis_line.alpha = normalizeAngle(place.axis + 0.5 * kPi);
  const auto isSideWall = [&](const LineSegment& s) {
    return angleBetweenLines(s.line, axis_line) <= params_.hallway_parallel_angle;
  };
  Opening opening;
  for (size_t i = 0; i < lines.size(); ++i) {
    const LineSegment& a = lines[i];
    if (!isSideWall(a)) continue;
    const double lateral_a = across.dot(0.5 * (a.start + a.end));
    for (size_t j = 0; j < lines.size(); ++j) {
      if (j == i) continue;
      const LineSegment& b = lines[j];
      if (!isSideWall(b)) continue;
      const double lateral_b = across.dot(0.5 * (b.start + b.end));
      if (lateral_a * lateral_b <= 0.0 || std::abs(lateral_a - lateral_b) > params_.hallway_step_max_offset)
        continue;
      // a's far end along the axis faces b's near end; each pair is taken once (a before b).
      const bool a_forward = along.dot(a.end) >= along.dot(a.start);
      const Eigen::Vector2d& a_far = a_forward ? a.end : a.start;
      const bool b_forward = along.dot(b.end) >= along.dot(b.start);
      const Eigen::Vector2d& b_near = b_forward ? b.start : b.end;
      if (!(along.dot(a_far) < along.dot(b_near))) continue;
      const Eigen::Vector2d edge_a = segmentEdge(points, a, a_forward);
      const Eigen::Vector2d edge_b = segmentEdge(points, b, !b_forward);
      if (makeOpening(points, edge_a, edge_b, OpeningSource::kHallwayStep, 0.8, &opening))
        addIfNew(opening, openings);
    }
  }
}

// (a) From the near side of a range discontinuity, the nearest point on the far side: the narrowest
// place of the gap. The search stops once no farther beam can come closer: a point at bearing
// offset delta from the near point P is at least |P| sin(delta) away (|P| beyond 90 degrees).
void OpeningExtractor::searchFarSide(const ScanPoints& points, const std::vector<LineSegment>& lines,
                                     size_t near, int direction, std::vector<Opening>* openings) const {
  const Eigen::Vector2d& p = points[near].p;
  const Eigen::Vector2d& near_unit = points.unit(near);
  const double near_range = points[near].range;
  // Near the end of the scanner's reach a wall fades into no-return beams without ending there.
  if (near_range > params_.max_range_fraction * points.rangeMax()) return;
  double best_squared = maxWidth() * maxWidth();
  size_t best = points.size();
  size_t beam = near;
  for (size_t k = 1; k < points.size(); ++k) {
    beam = stepBeam(points, beam, direction);
    if (beam >= points.size()) break;
    if (double(k) * points.increment() > kPi) break;
    // sin(offset) = |u_near x u_beam| while the offset is below 90 degrees.
    const Eigen::Vector2d& unit = points.unit(beam);
    const double lower_bound = near_unit.dot(unit) > 0.0 ? near_range * std::abs(cross2(near_unit, unit)) : near_range;
    if (lower_bound * lower_bound > best_squared) break;
    const BeamPoint& point = points[beam];
    if (point.status != BeamStatus::kValid) continue;
    const double squared = (point.p - p).squaredNorm();
    if (squared < best_squared) {
      best_squared = squared;
      best = beam;
    }
  }
  if (best >= points.size()) return;
  const Eigen::Vector2d edge_near = beamEdge(points, lines, near, direction);
  const Eigen::Vector2d edge_far = beamEdge(points, lines, best, -direction);
  const bool far_is_edge = isJumpEdge(points, best, -direction);
  const double support = 0.5 + 0.25 * (beam_line_[near] >= 0) + 0.25 * (beam_line_[best] >= 0);
  Opening opening;
  if (!makeOpening(points, edge_near, edge_far, OpeningSource::kRangeDiscontinuity,
                   far_is_edge ? support : 0.5 * support, &opening))
    return;
  // The far side is the middle of a surface, not a wall end: a gap seen past an occluding edge.
  if (!far_is_edge) opening.kind = OpeningKind::kUnknown;
  addIfNew(opening, openings);
}

void OpeningExtractor::findRangeDiscontinuities(const ScanPoints& points,
                                                const std::vector<LineSegment>& lines,
                                                std::vector<Opening>* openings) const {
  const size_t n = points.size();
  size_t first_valid = n;
  for (size_t i = 0; i < n; ++i)
    if (points[i].status == BeamStatus::kValid) {
      first_valid = i;
      break;
    }
  if (first_valid == n) return;
  // Walk the pairs of consecutive valid beams (through the seam of a circular scan).
  const size_t last = points.circular() ? first_valid + n : n - 1;
  size_t previous = first_valid;
  bool no_return_between = false;
  for (size_t v = first_valid + 1; v <= last; ++v) {
    const size_t i = points.wrap(v);
    const BeamStatus status = points[i].status;
    if (status == BeamStatus::kNoReturn) no_return_between = true;
    if (status != BeamStatus::kValid) continue;
    const double jump = points[i].range - points[previous].range;
    if (no_return_between || jump >= params_.jump_min) searchFarSide(points, lines, previous, +1, openings);
    if (no_return_between || -jump >= params_.jump_min) searchFarSide(points, lines, i, -1, openings);
    previous = i;
    no_return_between = false;
  }
}

void OpeningExtractor::extract(const ScanPoints& points, const std::vector<LineSegment>& lines,
                               const PlaceEstimate& place, std::vector<Opening>* openings) {
  openings->clear();
  if (points.numValid() < 2) return;
  labelBeams(points, lines);
  findCollinearGaps(points, lines, openings);
  findHallwaySteps(points, lines, place, openings);
  findRangeDiscontinuities(points, lines, openings);
  for (Opening& opening : *openings) opening.in_wall = inWall(opening, lines);
}

// An opening set in a wall has that wall beside it on one side at least: a line segment whose end
// is at one of its edges (within kMaxEdgeRefinement, the most an edge lies from its wall piece's
// last hit), which runs along the opening (collinear_angle) and away from it. A door next to a
// corner shows its wall on one side only: the jamb on the other is shorter than a line can be
// (door_jamb_min, 0.2 m, against lines.min_length, 0.4 m), so (b) never sees it; a wall at least a
// door and two lines long (every room's) leaves a line on one side. The gaps between table and
// chair legs, or between a leg and a wall across it, have none along them.
bool OpeningExtractor::inWall(const Opening& opening, const std::vector<LineSegment>& lines) const {
  if (opening.source == OpeningSource::kCollinearGap) return true;
  const Eigen::Vector2d across = opening.right - opening.left;
  if (!(across.norm() > 0.0)) return false;
  const Eigen::Vector2d across_unit = across.normalized();
  const double min_cos = std::cos(params_.collinear_angle);
  for (const LineSegment& segment : lines) {
    const Eigen::Vector2d along = segment.end - segment.start;
    if (!(along.norm() > 0.0)) continue;
    if (std::abs(along.normalized().dot(across_unit)) < min_cos) continue;
    for (const Eigen::Vector2d& edge : {opening.left, opening.right}) {
      const bool start_near = (segment.start - edge).norm() <= (segment.end - edge).norm();
      const Eigen::Vector2d& near = start_near ? segment.start : segment.end;
      const Eigen::Vector2d& far = start_near ? segment.end : segment.start;
      if ((near - edge).norm() <= kMaxEdgeRefinement && (far - opening.center).norm() > (near - opening.center).norm())
        return true;
    }
  }
  return false;
}

}  // namespace laser_features
