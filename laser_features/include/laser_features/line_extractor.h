// Line segments from a scan: adaptive-breakpoint segmentation, split-and-merge, a weighted total
// least-squares fit of (alpha, r) with its 2x2 covariance, and chi^2 merging of collinear
// neighbours, after Arras & Siegwart 1997 ("Feature extraction and scene interpretation for
// map-based navigation and map building", SPIE vol. 3210).
#pragma once

#include "laser_features/geometry.h"
#include "laser_features/line_fit.h"
#include "laser_features/scan.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace laser_features {

/// A fitted line and the part of it that the scan saw.
struct LineSegment {
  Line line;                                        // (alpha, r) and its covariance, scan frame
  Eigen::Vector2d start = Eigen::Vector2d::Zero();  // m, first point (counter-clockwise), projected on the line
  Eigen::Vector2d end = Eigen::Vector2d::Zero();    // m, last point, projected on the line
  uint32_t num_points = 0;                          // scan points used in the fit
  // Internal (counter-clockwise, ScanPoints) indices of the first and last point; for a segment that
  // runs through the seam of a circular scan last_beam < first_beam.
  uint32_t first_beam = 0;
  uint32_t last_beam = 0;

  double length() const { return (end - start).norm(); }
};

/// Parameters of LineExtractor (each with its unit and default).
struct LineExtractorParams {
  double range_sigma = 0.01;           // m, standard deviation of the range noise (sigma_rho)
  double range_sigma_per_meter = 0.0;  // m/m, extra range noise proportional to the range
  double bearing_sigma = 0.0;          // rad, standard deviation of the bearing noise (sigma_theta)
  double breakpoint_lambda = 0.1745;   // rad (10 deg), worst wall incidence still seen as continuous
                                       //   (adaptive breakpoint detector, Borges & Aldon 2004)
  double breakpoint_sigma_factor = 4.5;  // -, range-noise margin of the breakpoint distance, in sigma_rho
                                       //   (the paper's 3 sigma breaks walls at noise spikes once a
                                       //   scan has thousands of beams)
  double split_distance = 0.04;        // m, split a run where a point is farther than this from the chord
  double merge_chi2 = 13.82;           // -, merge neighbours when their (alpha, r) differ by less (chi^2, 2 dof, 99.9%)
  double trim_sigma = 3.0;             // -, drop an end point whose residual exceeds this many sigma
  int max_trim_per_end = 2;            // -, at most this many end points dropped per end
  double merge_max_gap = 0.2;          // m, neighbouring pieces whose ends are farther apart are not merged
  int min_points = 8;                  // -, fewer points make no line
  double min_length = 0.4;             // m, shorter segments make no line (0.2: 7.6% false lines on round furniture, see README)
};

class LineExtractor {
 public:
  using Params = LineExtractorParams;

  explicit LineExtractor(const Params& params = Params());

  const Params& params() const { return params_; }
  /// Pre-sizes the work buffers for scans of up to `beams` beams.
  void reserve(size_t beams);

  /// Appends the line segments of `points` to `lines` (cleared first), in counter-clockwise order.
  void extract(const ScanPoints& points, std::vector<LineSegment>* lines);

  /// Weighted total least-squares fit of the valid points with virtual indices in [begin, end]
  /// (see ScanPoints::wrap) with the covariance propagated from the range and bearing noise.
  /// Returns false when fewer than two points or the fit is degenerate.
  bool fitLine(const ScanPoints& points, size_t begin, size_t end, Line* line,
               uint32_t* num_points) const;

 private:
  /// A piece of the scan being split and merged: virtual indices [begin, end], inclusive.
  struct Piece {
    size_t begin = 0;
    size_t end = 0;
    uint32_t num_points = 0;
    bool fitted = false;
    bool stale = false;  // its range changed since the last fit
    Line line;
  };
  struct Interval {
    size_t begin;
    size_t end;
  };

  bool usable(const ScanPoints& points, size_t v) const;
  void markBreaks(const ScanPoints& points);
  bool isBreak(const ScanPoints& points, size_t a, size_t b) const;
  size_t findWalkStart(const ScanPoints& points, bool* continuous_ring) const;
  void collectRuns(const ScanPoints& points);
  bool deviatesFromFit(const ScanPoints& points, size_t begin, size_t end) const;
  void splitRun(const ScanPoints& points, size_t begin, size_t end);
  void fitPiece(const ScanPoints& points, Piece* piece) const;
  bool shouldMerge(const ScanPoints& points, const Piece& a, const Piece& b, size_t b_offset) const;
  void mergeNeighbours(const ScanPoints& points);
  void mergeAcrossSeam(const ScanPoints& points);
  void mergeAll(const ScanPoints& points);
  void normalizeRing(size_t n);
  static Piece shifted(const Piece& piece, size_t offset);
  void refineBoundaries(const ScanPoints& points);
  bool absorbCornerPiece(const ScanPoints& points, Piece* left, const Piece& middle, Piece* right) const;
  void absorbCornerPieces(const ScanPoints& points);
  void refineBoundary(const ScanPoints& points, Piece* left, Piece* right) const;
  void trimEnds(const ScanPoints& points, Piece* piece) const;
  size_t nextUsable(const ScanPoints& points, size_t i, size_t end) const;
  size_t previousUsable(const ScanPoints& points, size_t i, size_t begin) const;

  Params params_;
  WeightedLineFit line_fit_;
  std::vector<Piece> pieces_;
  std::vector<Interval> stack_;
  std::vector<uint8_t> ignored_;       // per beam: a valid point left out of every line (isolated clutter)
  std::vector<uint8_t> break_before_;  // per valid beam: a breakpoint separates it from the previous one
  double neighbour_break_ratio_ = 0.0;  // sin(dphi) / sin(lambda - dphi) for neighbouring beams
};

}  // namespace laser_features
