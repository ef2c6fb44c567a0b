// Shared checks for the laser_features tests.
#pragma once

#include "laser_features/feature_extractor.h"
#include "synthetic_scan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace laser_features {
namespace testing_helpers {

/// Index of the extracted line closest to `truth` (|d alpha| < 0.1 rad and |d r| < 0.1 m), or -1.
inline int findLine(const std::vector<LineSegment>& lines, const Line& truth) {
  int best = -1;
  double best_score = 1e9;
  for (size_t i = 0; i < lines.size(); ++i) {
    const Eigen::Vector2d d = lineDifference(lines[i].line, truth);
    if (std::abs(d.x()) > 0.1 || std::abs(d.y()) > 0.1) continue;
    const double score = std::abs(d.x()) + std::abs(d.y());
    if (score < best_score) {
      best_score = score;
      best = int(i);
    }
  }
  return best;
}

/// Normalized estimation error squared of a line estimate against the truth.
inline double lineNees(const Line& estimate, const Line& truth) {
  const Eigen::Vector2d d = lineDifference(estimate, truth);
  return d.dot(estimate.cov.inverse() * d);
}

/// Every number in the features is finite and every confidence in [0, 1].
inline ::testing::AssertionResult allFinite(const Features& f) {
  for (const LineSegment& s : f.lines)
    if (!std::isfinite(s.line.alpha) || !std::isfinite(s.line.r) || !s.line.cov.allFinite() ||
        !s.start.allFinite() || !s.end.allFinite() || s.line.r < 0.0 || s.line.alpha <= -kPi ||
        s.line.alpha > kPi)
      return ::testing::AssertionFailure() << "bad line";
  for (const Corner& c : f.corners)
    if (!c.position.allFinite() || !std::isfinite(c.theta) || !c.cov.allFinite() ||
        !(c.confidence >= 0.0 && c.confidence <= 1.0))
      return ::testing::AssertionFailure() << "bad corner";
  for (const Opening& o : f.openings)
    if (!o.left.allFinite() || !o.right.allFinite() || !o.center.allFinite() || !std::isfinite(o.theta) ||
        !std::isfinite(o.width) || !(o.confidence >= 0.0 && o.confidence <= 1.0))
      return ::testing::AssertionFailure() << "bad opening";
  if (!(f.place_confidence >= 0.0 && f.place_confidence <= 1.0))
    return ::testing::AssertionFailure() << "bad place confidence";
  return ::testing::AssertionSuccess();
}

}  // namespace testing_helpers
}  // namespace laser_features
