// LineExtractor, merging (Arras & Siegwart 1997): neighbouring pieces whose lines agree become one,
// also across the seam of a circular scan. The class: line_extractor.h.
#include "laser_features/line_extractor.h"

namespace laser_features {

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

}  // namespace laser_features
