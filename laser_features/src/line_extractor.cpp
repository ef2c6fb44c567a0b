// LineExtractor: construction, the usable-point helpers, fitting, the ring of pieces, and extract(),
// which runs the steps (line_extractor_split.cpp, line_extractor_merge.cpp,
// line_extractor_boundaries.cpp).
#include "laser_features/line_extractor.h"
#include "no_index.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace laser_features {

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

bool LineExtractor::fitLine(const ScanPoints& points, size_t begin, size_t end, Line* line,
                            uint32_t* num_points) const {
  return line_fit_.fit(points, begin, end, nullptr, line, num_points);
}

void LineExtractor::fitPiece(const ScanPoints& points, Piece* piece) const {
  piece->fitted = piece->begin < piece->end &&
                  line_fit_.fit(points, piece->begin, piece->end, &ignored_, &piece->line, &piece->num_points);
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
