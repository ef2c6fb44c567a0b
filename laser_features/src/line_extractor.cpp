#include "laser_features/line_extractor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace laser_features {

namespace {

constexpr size_t kNone = std::numeric_limits<size_t>::max();
// Points on each side of the boundary of two neighbouring pieces that may change side.
constexpr size_t kBoundaryWindow = 3;

}  // namespace

namespace {

LineExtractorParams sanitized(LineExtractorParams p) {
  // Zero noise would make every weight infinite and every covariance singular.
  p.range_sigma = std::max(p.range_sigma, 1e-6);
  p.range_sigma_per_meter = std::max(p.range_sigma_per_meter, 0.0);
  p.bearing_sigma = std::max(p.bearing_sigma, 0.0);
  p.min_points = std::max(p.min_points, 2);
  p.max_trim_per_end = std::max(p.max_trim_per_end, 0);
  return p;
}

}  // namespace

LineExtractor::LineExtractor(const Params& params)
    : params_(sanitized(params)),
      line_fit_(params_.range_sigma, params_.range_sigma_per_meter, params_.bearing_sigma) {
  reserve(1024);
}

void LineExtractor::reserve(size_t beams) {
  pieces_.reserve(beams);
  stack_.reserve(beams);
  ignored_.reserve(beams);
  break_before_.reserve(beams);
}

bool LineExtractor::usable(const ScanPoints& points, size_t v) const {
  const size_t i = points.wrap(v);
  return points[i].status == BeamStatus::kValid && !ignored_[i];
}

size_t LineExtractor::nextUsable(const ScanPoints& points, size_t i, size_t end) const {
  for (++i; i <= end; ++i)
    if (usable(points, i)) return i;
  return kNone;
}

size_t LineExtractor::previousUsable(const ScanPoints& points, size_t i, size_t begin) const {
  while (i > begin) {
    --i;
    if (usable(points, i)) return i;
  }
  return kNone;
}

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

bool LineExtractor::fitLine(const ScanPoints& points, size_t begin, size_t end, Line* line,
                            uint32_t* num_points) const {
  return line_fit_.fit(points, begin, end, nullptr, line, num_points);
}

void LineExtractor::fitPiece(const ScanPoints& points, Piece* piece) const {
  piece->fitted = piece->begin < piece->end &&
                  line_fit_.fit(points, piece->begin, piece->end, &ignored_, &piece->line, &piece->num_points);
}

// Merge step (Arras & Siegwart 1997): neighbouring pieces (sharing their split point, or with at most
// merge_max_gap between their end points, which joins a wall broken by noise or by a small object in
// front of it) are merged when their (alpha, r) agree in a chi^2 test with 2 degrees of freedom;
// lineMahalanobisSq handles the angle wrap-around and the sign ambiguity of lines near the origin.
// `b_offset` shifts b's indices (by the scan size, across the seam of a circular scan).
bool LineExtractor::shouldMerge(const ScanPoints& points, const Piece& a, const Piece& b,
                                size_t b_offset) const {
  if (!a.fitted || !b.fitted || b.begin + b_offset < a.end) return false;
  const Eigen::Vector2d& a_last = points[points.wrap(a.end)].p;
  const Eigen::Vector2d& b_first = points[points.wrap(b.begin)].p;
  return (b_first - a_last).squaredNorm() <= params_.merge_max_gap * params_.merge_max_gap &&
         lineMahalanobisSq(a.line, b.line) <= params_.merge_chi2;
}

void LineExtractor::mergeNeighbours(const ScanPoints& points) {
  size_t kept = 0;
  for (size_t i = 0; i < pieces_.size(); ++i) {
    if (kept > 0 && shouldMerge(points, pieces_[kept - 1], pieces_[i], 0)) {
      Piece merged = pieces_[kept - 1];
      merged.end = pieces_[i].end;
      fitPiece(points, &merged);
      if (merged.fitted) {
        pieces_[kept - 1] = merged;
        continue;
      }
    }
    pieces_[kept++] = pieces_[i];
  }
  pieces_.resize(kept);
}

// Pieces of a circular scan form a ring. After an operation across the seam, bring every piece's begin
// back into [0, n) and sort by begin: the last piece is then the one before the seam, and the first
// piece's indices shifted by n follow it.
void LineExtractor::normalizeRing(size_t n) {
  for (Piece& piece : pieces_) {
    if (piece.begin >= n) {
      piece.begin -= n;
      piece.end -= n;
    }
  }
  std::sort(pieces_.begin(), pieces_.end(), [](const Piece& a, const Piece& b) { return a.begin < b.begin; });
}

LineExtractor::Piece LineExtractor::shifted(const Piece& piece, size_t offset) {
  Piece copy = piece;
  copy.begin += offset;
  copy.end += offset;
  return copy;
}

// A wall crossing the seam of a circular scan is the last and the first piece; merge them into one
// piece that runs through the seam (virtual indices beyond the scan size).
void LineExtractor::mergeAcrossSeam(const ScanPoints& points) {
  const size_t n = points.size();
  while (pieces_.size() >= 2 && shouldMerge(points, pieces_.back(), pieces_.front(), n)) {
    Piece merged = pieces_.back();
    merged.end = pieces_.front().end + n;
    fitPiece(points, &merged);
    if (!merged.fitted) return;
    pieces_.back() = merged;
    pieces_.erase(pieces_.begin());
  }
}

void LineExtractor::mergeAll(const ScanPoints& points) {
  mergeNeighbours(points);
  if (points.circular()) mergeAcrossSeam(points);
}

void LineExtractor::refineBoundaries(const ScanPoints& points) {
  for (size_t i = 0; i + 1 < pieces_.size(); ++i) refineBoundary(points, &pieces_[i], &pieces_[i + 1]);
  if (points.circular() && pieces_.size() >= 2) {
    // The corner where a continuous ring was closed: the first piece follows the last one.
    const size_t n = points.size();
    Piece first = shifted(pieces_.front(), n);
    refineBoundary(points, &pieces_.back(), &first);
    pieces_.front() = first;
    normalizeRing(n);
  }
  for (Piece& piece : pieces_) {
    if (!piece.stale) continue;
    fitPiece(points, &piece);
    piece.stale = false;
  }
}

// Neighbouring pieces from one split share their split point and, with noise, the split can land a
// beam or two off the true corner. Move the boundary to where the summed squared residuals of the two
// lines are least; both pieces are refitted after all boundaries have moved.
void LineExtractor::refineBoundary(const ScanPoints& points, Piece* left, Piece* right) const {
  if (!left->fitted || !right->fitted || left->end != right->begin) return;
  const size_t lo = std::max(left->begin + 1, left->end >= kBoundaryWindow ? left->end - kBoundaryWindow : 0);
  const size_t hi = std::min(right->begin + kBoundaryWindow, right->end - 1);
  if (!(lo < hi)) return;
  double best_cost = std::numeric_limits<double>::infinity();
  size_t best_k = kNone;
  // Boundary k: points up to k go left, the others right.
  const HesseLine left_line(left->line), right_line(right->line);
  for (size_t k = lo; k <= hi; ++k) {
    if (!usable(points, k)) continue;
    double cost = 0.0;
    for (size_t v = lo; v <= hi + 1; ++v) {
      if (!usable(points, v)) continue;
      const double residual = (v <= k ? left_line : right_line).distance(points[points.wrap(v)].p);
      cost += residual * residual;
    }
    if (cost < best_cost) {
      best_cost = cost;
      best_k = k;
    }
  }
  if (best_k == kNone) return;
  const size_t right_begin = nextUsable(points, best_k, right->end);
  if (right_begin == kNone || right_begin >= right->end) return;
  left->end = best_k;
  right->begin = right_begin;
  left->stale = right->stale = true;  // refitted once all boundaries have moved
}

// With noise, the split can cut a corner twice and leave a short piece of points from both walls
// between them. When its points fit the lines on either side (each within split_distance of its line,
// with one boundary between them), hand them over and drop the piece.
bool LineExtractor::absorbCornerPiece(const ScanPoints& points, Piece* left, const Piece& middle,
                                      Piece* right) const {
  if (!left->fitted || !right->fitted || left->end != middle.begin || middle.end != right->begin) return false;
  double best_cost = std::numeric_limits<double>::infinity();
  size_t best_k = kNone;
  const HesseLine left_line(left->line), right_line(right->line);
  for (size_t k = middle.begin; k < middle.end; ++k) {
    if (!usable(points, k)) continue;
    double cost = 0.0;
    bool fits = true;
    for (size_t v = middle.begin; v <= middle.end && fits; ++v) {
      if (!usable(points, v)) continue;
      const double residual = (v <= k ? left_line : right_line).distance(points[points.wrap(v)].p);
      fits = std::abs(residual) <= params_.split_distance;
      cost += residual * residual;
    }
    if (fits && cost < best_cost) {
      best_cost = cost;
      best_k = k;
    }
  }
  if (best_k == kNone) return false;
  const size_t right_begin = nextUsable(points, best_k, right->end);
  if (right_begin == kNone || right_begin >= right->end) return false;
  left->end = best_k;
  right->begin = right_begin;
  fitPiece(points, left);
  fitPiece(points, right);
  return left->fitted && right->fitted;
}

void LineExtractor::absorbCornerPieces(const ScanPoints& points) {
  const auto isSmall = [&](const Piece& piece) { return piece.num_points < uint32_t(2 * params_.min_points); };
  size_t kept = 0;
  for (size_t i = 0; i < pieces_.size(); ++i) {
    if (isSmall(pieces_[i]) && kept > 0 && i + 1 < pieces_.size() &&
        absorbCornerPiece(points, &pieces_[kept - 1], pieces_[i], &pieces_[i + 1]))
      continue;
    pieces_[kept++] = pieces_[i];
  }
  pieces_.resize(kept);
  if (!points.circular() || pieces_.size() < 3) return;
  // Around the seam: the last piece between its predecessor and the first piece, then the first
  // piece between the last piece and the second one (indices shifted by n to follow the last).
  const size_t n = points.size();
  Piece after_seam = shifted(pieces_.front(), n);
  if (isSmall(pieces_.back()) &&
      absorbCornerPiece(points, &pieces_[pieces_.size() - 2], pieces_.back(), &after_seam)) {
    pieces_.front() = after_seam;
    pieces_.pop_back();
    normalizeRing(n);
  }
  if (pieces_.size() < 3 || !isSmall(pieces_.front())) return;
  Piece second = shifted(pieces_[1], n);
  if (absorbCornerPiece(points, &pieces_.back(), shifted(pieces_.front(), n), &second)) {
    pieces_[1] = second;
    pieces_.erase(pieces_.begin());
    normalizeRing(n);
  }
}

// Drops end points whose residual is beyond trim_sigma standard deviations (typically a point of
// the neighbouring wall at a corner, or a mixed pixel at an edge), then refits.
void LineExtractor::trimEnds(const ScanPoints& points, Piece* piece) const {
  const double sigma_theta2 = params_.bearing_sigma * params_.bearing_sigma;
  const auto isOutlier = [&](const HesseLine& line, size_t v) {
    const size_t i = points.wrap(v);
    const double nu = line.normal.dot(points.unit(i));
    const double sigma_rho = line_fit_.rangeSigma(points[i].range);
    // Variance of the point across the line: range noise along u, bearing noise along v.
    const double var_across = sigma_rho * sigma_rho * nu * nu +
                              sigma_theta2 * points[i].range * points[i].range * (1.0 - nu * nu);
    const double residual = line.distance(points[i].p);
    return residual * residual > params_.trim_sigma * params_.trim_sigma * var_across;
  };
  for (int iteration = 0; iteration < params_.max_trim_per_end && piece->fitted; ++iteration) {
    bool trimmed = false;
    const HesseLine line(piece->line);
    if (isOutlier(line, piece->begin)) {
      const size_t next = nextUsable(points, piece->begin, piece->end);
      if (next == kNone || next >= piece->end) return;
      piece->begin = next;
      trimmed = true;
    }
    if (isOutlier(line, piece->end)) {
      const size_t previous = previousUsable(points, piece->end, piece->begin);
      if (previous == kNone || previous <= piece->begin) return;
      piece->end = previous;
      trimmed = true;
    }
    if (!trimmed) return;
    fitPiece(points, piece);
  }
}

void LineExtractor::extract(const ScanPoints& points, std::vector<LineSegment>* lines) {
  lines->clear();
  pieces_.clear();
  if (points.numValid() < 2) return;
  const size_t n = points.size();
  if (pieces_.capacity() < n) reserve(n);  // only when a longer scan than ever before arrives
  ignored_.assign(n, 0);
  const double step = points.increment();
  neighbour_break_ratio_ = step < params_.breakpoint_lambda
                               ? std::sin(step) / std::sin(params_.breakpoint_lambda - step)
                               : std::numeric_limits<double>::infinity();
  markBreaks(points);

  // 1. Split the runs; 2. fit, merge collinear neighbours, absorb corner pieces, refine the
  // boundaries, trim the ends, merge again (pieces cleared of stray points may now agree), trim.
  collectRuns(points);
  for (Piece& piece : pieces_) fitPiece(points, &piece);
  if (points.circular()) normalizeRing(n);
  mergeAll(points);
  absorbCornerPieces(points);
  refineBoundaries(points);
  for (Piece& piece : pieces_) trimEnds(points, &piece);
  mergeAll(points);
  for (Piece& piece : pieces_) trimEnds(points, &piece);

  // 3. Output the pieces that are long and dense enough.
  for (const Piece& piece : pieces_) {
    if (!piece.fitted || piece.num_points < uint32_t(params_.min_points)) continue;
    LineSegment segment;
    segment.line = piece.line;
    segment.start = projectOntoLine(piece.line, points[points.wrap(piece.begin)].p);
    segment.end = projectOntoLine(piece.line, points[points.wrap(piece.end)].p);
    if (segment.length() < params_.min_length || !segment.start.allFinite() || !segment.end.allFinite())
      continue;
    segment.num_points = piece.num_points;
    segment.first_beam = uint32_t(points.wrap(piece.begin));
    segment.last_beam = uint32_t(points.wrap(piece.end));
    lines->push_back(segment);
  }
}

}  // namespace laser_features
