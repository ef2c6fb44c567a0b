// LineExtractor, where the pieces end: the boundary of neighbouring pieces moved to where their
// residuals are least, short pieces at corners handed over to their neighbours, outlying end points
// trimmed. The class: line_extractor.h.
#include "laser_features/line_extractor.h"
#include "no_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace laser_features {

namespace {

// Points on each side of the boundary of two neighbouring pieces that may change side.
constexpr size_t kBoundaryWindow = 3;

}  // namespace

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

}  // namespace laser_features
