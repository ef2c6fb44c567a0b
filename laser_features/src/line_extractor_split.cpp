// LineExtractor, step 1: the scan cut into pieces. Breakpoints (Borges & Aldon 2004) divide it into
// runs of points, and each run is split where it bends (the split of split-and-merge, Arras &
// Siegwart 1997). The class: line_extractor.h.
#include "laser_features/line_extractor.h"
#include "no_index.h"

#include <cmath>

namespace laser_features {

// Marks every valid point that follows a breakpoint (from the previous valid point, through the seam
// for a circular scan), once per scan.
void LineExtractor::markBreaks(const ScanPoints& points) {
  const size_t n = points.size();
  break_before_.assign(n, 0);
  size_t first = kNone, previous = kNone;
  for (size_t i = 0; i < n; ++i) {
    const BeamPoint& point = points[i];
    if (point.status != BeamStatus::kValid) continue;
    if (previous != kNone && previous + 1 == i) {
      // Neighbouring beams, the common case, inline: the threshold of isBreak with the cached ratio.
      const BeamPoint& before = points[previous];
      const double max_distance = before.range * neighbour_break_ratio_ +
                                  params_.breakpoint_sigma_factor * line_fit_.rangeSigma(before.range);
      break_before_[i] = (point.p - before.p).squaredNorm() > max_distance * max_distance;
    } else if (previous != kNone) {
      break_before_[i] = isBreak(points, previous, i);
    }
    if (first == kNone) first = i;
    previous = i;
  }
  if (points.circular() && first != kNone && previous != first)
    break_before_[first] = isBreak(points, previous, first + n);
}

// Adaptive breakpoint detector (Borges & Aldon 2004, "Line extraction in 2D range images for mobile
// robotics", J. Intell. Robot. Syst. 40(3)): consecutive points a, b belong to different objects
// when  |p_b - p_a| > rho_a sin(dphi) / sin(lambda - dphi) + k sigma_r,  i.e. when the surface
// between them would be seen at an incidence shallower than lambda. `a` < `b` are virtual indices.
bool LineExtractor::isBreak(const ScanPoints& points, size_t a, size_t b) const {
  const double dphi = double(b - a) * points.increment();
  if (dphi >= params_.breakpoint_lambda) return true;
  const BeamPoint& pa = points[points.wrap(a)];
  const BeamPoint& pb = points[points.wrap(b)];
  // Neighbouring beams (the common case) use the ratio computed once per scan.
  const double ratio = b - a == 1 ? neighbour_break_ratio_
                                  : std::sin(dphi) / std::sin(params_.breakpoint_lambda - dphi);
  const double max_distance = pa.range * ratio + params_.breakpoint_sigma_factor * line_fit_.rangeSigma(pa.range);
  return (pb.p - pa.p).squaredNorm() > max_distance * max_distance;
}

// Where the walk along the scan starts. A circular scan starts just after a break, so that no run of
// points crosses the seam between the last and the first beam. A closed room seen all around has no
// break (a "continuous ring"): it starts at the farthest point, which on a ring of walls around the
// sensor is a corner (the range along a straight wall has no interior maximum).
size_t LineExtractor::findWalkStart(const ScanPoints& points, bool* continuous_ring) const {
  *continuous_ring = false;
  if (!points.circular()) return 0;
  const size_t n = points.size();
  size_t first_valid = kNone, last_valid = kNone, farthest = kNone;
  for (size_t i = 0; i < n; ++i) {
    if (points[i].status != BeamStatus::kValid) continue;
    if (first_valid == kNone) first_valid = i;
    else if (break_before_[i]) return i;
    if (farthest == kNone || points[i].range > points[farthest].range) farthest = i;
    last_valid = i;
  }
  if (first_valid == kNone) return 0;
  if (break_before_[first_valid]) return first_valid;  // the break is at the seam
  *continuous_ring = last_valid != first_valid;
  return farthest;
}

// Runs: maximal sequences of valid points without a breakpoint. Runs with fewer than min_points
// points are ignored (isolated clutter, or a noise spike that broke a wall); the others are split.
// A continuous ring is closed: it runs from its start corner all around back to it, and is first cut
// at the point farthest from that corner, so that both halves have a proper chord.
void LineExtractor::collectRuns(const ScanPoints& points) {
  const size_t n = points.size();
  bool continuous_ring = false;
  const size_t start = findWalkStart(points, &continuous_ring);
  if (continuous_ring) {
    const Eigen::Vector2d& corner = points[start].p;
    size_t opposite = kNone;
    double farthest = 0.0;
    points.forEachIndex(start + 1, start + n - 1, [&](size_t i, size_t v) {
      if (points[i].status != BeamStatus::kValid) return;
      const double distance = (points[i].p - corner).squaredNorm();
      if (distance > farthest) farthest = distance, opposite = v;
    });
    if (opposite != kNone && points.numValid() >= size_t(params_.min_points)) {
      splitRun(points, start, opposite);
      splitRun(points, opposite, start + n);
      return;
    }
  }
  size_t run_begin = kNone, previous = kNone, run_points = 0;
  const auto closeRun = [&]() {
    if (run_begin == kNone) return;
    if (run_points >= size_t(params_.min_points)) {
      splitRun(points, run_begin, previous);
    } else {
      for (size_t v = run_begin; v <= previous; ++v) ignored_[points.wrap(v)] = 1;
    }
  };
  points.forEachIndex(start, start + n - 1, [&](size_t i, size_t v) {
    if (points[i].status != BeamStatus::kValid) return;
    if (previous != kNone && break_before_[i]) {
      closeRun();
      run_begin = kNone;
    }
    if (run_begin == kNone) {
      run_begin = v;
      run_points = 0;
    }
    ++run_points;
    previous = v;
  });
  closeRun();
}

// Unweighted total least-squares line through the valid points of [begin, end] (the fit below with
// equal weights); true when some interior point lies farther than split_distance from it.
bool LineExtractor::deviatesFromFit(const ScanPoints& points, size_t begin, size_t end) const {
  const Eigen::Vector2d shift = points[points.wrap(begin)].p;
  double n = 0.0, Sx = 0.0, Sy = 0.0, Sxx = 0.0, Syy = 0.0, Sxy = 0.0;
  points.forEachIndex(begin, end, [&](size_t i, size_t) {
    const BeamPoint& point = points[i];
    if (point.status != BeamStatus::kValid) return;
    const double dx = point.p.x() - shift.x(), dy = point.p.y() - shift.y();
    n += 1.0;
    Sx += dx;
    Sy += dy;
    Sxx += dx * dx;
    Syy += dy * dy;
    Sxy += dx * dy;
  });
  const double mx = Sx / n, my = Sy / n;
  const double alpha =
      0.5 * std::atan2(-2.0 * (Sxy / n - mx * my), (Syy / n - my * my) - (Sxx / n - mx * mx));
  const Eigen::Vector2d normal = unitVector(alpha);
  const double offset = normal.dot(shift + Eigen::Vector2d(mx, my));  // the line: normal . p = offset
  // The ends are split points, possibly a beam into the neighbouring wall: only the interior counts.
  bool deviates = false;
  if (end > begin + 1) {
    points.forEachIndex(begin + 1, end - 1, [&](size_t i, size_t) {
      const BeamPoint& point = points[i];
      deviates |= point.status == BeamStatus::kValid &&
                  std::abs(normal.dot(point.p) - offset) > params_.split_distance;
    });
  }
  return deviates;
}

// Iterative end-point fit, the "split" of split-and-merge (Arras & Siegwart 1997): split [begin, end]
// at the point farthest from the chord while it lies farther than split_distance from the chord and
// some interior point lies that far from the fitted line (the chord alone runs between two noisy
// points, and would cut straight walls at noise spikes). The split point ends the left piece and
// starts the right one; the boundary is refined after fitting. Pieces come out left to right.
void LineExtractor::splitRun(const ScanPoints& points, size_t begin, size_t end) {
  stack_.clear();
  stack_.push_back({begin, end});
  while (!stack_.empty()) {
    const Interval interval = stack_.back();
    stack_.pop_back();
    const Eigen::Vector2d& a = points[points.wrap(interval.begin)].p;
    const Eigen::Vector2d chord = points[points.wrap(interval.end)].p - a;
    const double chord_length = chord.norm();
    // Compare |chord x (p - a)| (distance times chord length) to avoid a division per point.
    double worst = params_.split_distance * chord_length;
    size_t split = kNone;
    if (interval.end > interval.begin + 1) {
      points.forEachIndex(interval.begin + 1, interval.end - 1, [&](size_t i, size_t v) {
        const BeamPoint& point = points[i];
        if (point.status != BeamStatus::kValid) return;
        const double deviation = chord_length > 1e-9 ? std::abs(cross2(chord, point.p - a))
                                                     : (point.p - a).norm() * 1e-9;
        if (deviation > worst) {
          worst = deviation;
          split = v;
        }
      });
    }
    if (split != kNone && !deviatesFromFit(points, interval.begin, interval.end)) split = kNone;
    if (split == kNone) {
      Piece piece;
      piece.begin = interval.begin;
      piece.end = interval.end;
      pieces_.push_back(piece);
    } else {
      stack_.push_back({split, interval.end});
      stack_.push_back({interval.begin, split});
    }
  }
}

}  // namespace laser_features
