// Line extraction on analytic scans with 1 cm range noise: accuracy, covariance consistency (NEES),
// the seam of circular scans, 180-degree clockwise scanners at several resolutions.
#include "laser_features/line_extractor.h"

#include "synthetic_scan.h"
#include "test_helpers.h"

#include <gtest/gtest.h>

#include <random>

namespace laser_features {
namespace {

using namespace synthetic;
using testing_helpers::findLine;
using testing_helpers::lineNees;

constexpr double kSigma = 0.01;  // m, range noise of the simulated scanner

std::vector<LineSegment> extractLines(const ScanView& view, const LineExtractor::Params& params = {}) {
  ScanPoints points;
  EXPECT_EQ(validateScan(view), "");
  points.assign(view);
  LineExtractor extractor(params);
  std::vector<LineSegment> lines;
  extractor.extract(points, &lines);
  return lines;
}

TEST(LineExtractor, RecoversTheWallsOfARoom) {
  const World room = rectangularRoom(6.0, 4.0);
  const Pose2D sensor{2.2, 1.7, 0.3};
  const ScanSpec spec = ScanSpec::full(720);
  std::mt19937 rng(1);
  const std::vector<float> ranges = simulateScan(room, sensor, spec, kSigma, &rng);
  const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
  ASSERT_EQ(lines.size(), 4u);
  for (const Wall& wall : room.walls) {
    const Line truth = wallInSensorFrame(wall, sensor);
    const int i = findLine(lines, truth);
    ASSERT_GE(i, 0);
    const Line& estimate = lines[size_t(i)].line;
    const Eigen::Vector2d d = lineDifference(estimate, truth);
    EXPECT_LT(std::abs(d.x()), 4.0 * std::sqrt(estimate.cov(0, 0)) + 1e-4);
    EXPECT_LT(std::abs(d.y()), 4.0 * std::sqrt(estimate.cov(1, 1)) + 1e-4);
    EXPECT_LT(std::abs(d.y()), 0.01);  // a few sigma of one beam, much less for a whole wall
    EXPECT_GE(estimate.r, 0.0);
    // End points lie on the line, near the room's corners.
    EXPECT_NEAR(signedDistanceToLine(estimate, lines[size_t(i)].start), 0.0, 1e-9);
    EXPECT_NEAR(signedDistanceToLine(estimate, lines[size_t(i)].end), 0.0, 1e-9);
    const Eigen::Vector2d a = pointInSensorFrame(wall.a, sensor), b = pointInSensorFrame(wall.b, sensor);
    const double to_corners = std::min((lines[size_t(i)].start - a).norm() + (lines[size_t(i)].end - b).norm(),
                                       (lines[size_t(i)].start - b).norm() + (lines[size_t(i)].end - a).norm());
    EXPECT_LT(to_corners, 0.15);
  }
}

// Normalized estimation error squared: consistent covariances give a mean of 2 (2 dof).
TEST(LineExtractor, CovarianceIsConsistentNees) {
  const World room = rectangularRoom(6.0, 4.0);
  const ScanSpec spec = ScanSpec::full(720);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(1.0, 5.0), y(1.0, 3.0), heading(-kPi, kPi);
  double nees_sum = 0.0;
  int matched = 0, missed = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2D sensor{x(rng), y(rng), heading(rng)};
    const std::vector<float> ranges = simulateScan(room, sensor, spec, kSigma, &rng);
    const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
    for (const Wall& wall : room.walls) {
      const Line truth = wallInSensorFrame(wall, sensor);
      const int i = findLine(lines, truth);
      if (i < 0) {
        ++missed;
        continue;
      }
      nees_sum += lineNees(lines[size_t(i)].line, truth);
      ++matched;
    }
  }
  const double mean_nees = nees_sum / matched;
  std::printf("mean NEES over %d lines: %.3f (missed %d)\n", matched, mean_nees, missed);
  EXPECT_EQ(missed, 0);
  EXPECT_GE(mean_nees, 1.5);
  EXPECT_LE(mean_nees, 2.6);
}

// The same with bearing noise as well (0.3 degree), declared in the parameters.
TEST(LineExtractor, CovarianceWithBearingNoiseIsConsistentNees) {
  const World room = rectangularRoom(6.0, 4.0);
  const ScanSpec spec = ScanSpec::full(720);
  constexpr double kBearingSigma = 0.005;
  LineExtractor::Params params;
  params.bearing_sigma = kBearingSigma;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> x(1.0, 5.0), y(1.0, 3.0), heading(-kPi, kPi);
  double nees_sum = 0.0, nees_ignoring_bearing_sum = 0.0;
  int matched = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2D sensor{x(rng), y(rng), heading(rng)};
    const std::vector<float> ranges = simulateScan(room, sensor, spec, kSigma, &rng, kBearingSigma);
    const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges), params);
    const std::vector<LineSegment> lines_range_only = extractLines(makeView(spec, ranges));
    for (const Wall& wall : room.walls) {
      const Line truth = wallInSensorFrame(wall, sensor);
      const int i = findLine(lines, truth);
      const int j = findLine(lines_range_only, truth);
      if (i < 0 || j < 0) continue;
      nees_sum += lineNees(lines[size_t(i)].line, truth);
      nees_ignoring_bearing_sum += lineNees(lines_range_only[size_t(j)].line, truth);
      ++matched;
    }
  }
  const double mean_nees = nees_sum / matched;
  std::printf("mean NEES with bearing noise: %.3f (covariance without the bearing term: %.3f)\n", mean_nees,
              nees_ignoring_bearing_sum / matched);
  EXPECT_GE(matched, 780);
  EXPECT_GE(mean_nees, 1.5);
  EXPECT_LE(mean_nees, 2.6);
  EXPECT_GT(nees_ignoring_bearing_sum / matched, 3.0);  // the bearing term matters at this noise
}

// The predicted covariance of one wall against the Monte-Carlo covariance of its estimates.
TEST(LineExtractor, CovarianceMatchesMonteCarlo) {
  World world;
  world.addWall(3.0, -4.0, 3.0, 4.0);
  const Pose2D sensor{0.0, 0.0, 0.4};
  const ScanSpec spec = ScanSpec::full(720);
  const Line truth = wallInSensorFrame(world.walls[0], sensor);
  std::mt19937 rng(3);
  std::vector<Eigen::Vector2d> errors;
  Eigen::Matrix2d predicted = Eigen::Matrix2d::Zero();
  for (int trial = 0; trial < 500; ++trial) {
    const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, &rng);
    const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
    ASSERT_EQ(lines.size(), 1u);
    errors.push_back(lineDifference(lines[0].line, truth));
    predicted += lines[0].line.cov;
  }
  predicted /= double(errors.size());
  Eigen::Matrix2d sample = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector2d& e : errors) sample += e * e.transpose();
  sample /= double(errors.size());
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(sample(k, k) / predicted(k, k), 1.0, 0.2) << k;
  const double predicted_correlation = predicted(0, 1) / std::sqrt(predicted(0, 0) * predicted(1, 1));
  const double sample_correlation = sample(0, 1) / std::sqrt(sample(0, 0) * sample(1, 1));
  EXPECT_NEAR(sample_correlation, predicted_correlation, 0.15);
}

// A circular scan is cut at its first beam; a wall crossing that cut is one line.
TEST(LineExtractor, CircularScanWallThroughFirstBeamIsOneLine) {
  const World room = rectangularRoom(6.0, 4.0);
  std::mt19937 rng(11);
  for (const bool clockwise : {false, true}) {
    for (const double heading : {0.0, 0.05, kPi / 2, kPi, -kPi / 2 + 0.02}) {
      const Pose2D sensor{2.5, 1.8, heading};
      ScanSpec spec = ScanSpec::full(720, 0.0);  // beam 0 straight ahead, into the middle of a wall
      if (clockwise) spec.angle_increment = -spec.angle_increment;
      const std::vector<float> ranges = simulateScan(room, sensor, spec, kSigma, &rng);
      const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
      EXPECT_EQ(lines.size(), 4u) << "heading " << heading << " clockwise " << clockwise;
      for (const Wall& wall : room.walls) {
        const Line truth = wallInSensorFrame(wall, sensor);
        int matches = 0;
        for (const LineSegment& s : lines) {
          const Eigen::Vector2d d = lineDifference(s.line, truth);
          matches += std::abs(d.x()) < 0.1 && std::abs(d.y()) < 0.1;
        }
        EXPECT_EQ(matches, 1) << "heading " << heading;
      }
      // Exactly one segment runs through the seam (its last beam comes before its first).
      int through_seam = 0;
      for (const LineSegment& s : lines) through_seam += s.last_beam < s.first_beam;
      EXPECT_EQ(through_seam, 1) << "heading " << heading;
    }
  }
}

// A room with a door on the seam side: the run containing beam 0 starts after a break, still one
// line per wall piece.
TEST(LineExtractor, CircularScanWithBreaksKeepsSeamWallWhole) {
  World world;
  world.addWall(3.0, -3.0, 3.0, 3.0);  // wall ahead, crossing beam 0
  world.addWall(-3.0, -3.0, -3.0, 3.0);
  world.addWall(-3.0, 3.0, 1.0, 3.0);  // top wall with a gap (x in [1, 3]) -> a break
  world.addWall(-3.0, -3.0, 3.0, -3.0);
  const Pose2D sensor{0.0, 0.0, 0.0};
  const ScanSpec spec = ScanSpec::full(1440, 0.0);
  std::mt19937 rng(5);
  const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, &rng);
  const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
  Line ahead;
  ahead.alpha = 0.0;
  ahead.r = 3.0;
  int count = 0;
  for (const LineSegment& s : lines) count += std::abs(lineDifference(s.line, ahead).x()) < 0.05 &&
                                              std::abs(lineDifference(s.line, ahead).y()) < 0.05;
  EXPECT_EQ(count, 1);
  EXPECT_EQ(lines.size(), 4u);
}

TEST(LineExtractor, HalfScanClockwiseAtEveryResolution) {
  const World room = rectangularRoom(6.0, 4.0);
  const Pose2D sensor{1.5, 1.6, 0.1};
  std::mt19937 rng(13);
  for (const size_t beams : {361u, 720u, 1440u, 2880u}) {
    for (const bool clockwise : {true, false}) {
      const ScanSpec spec = ScanSpec::half(beams, clockwise);
      const std::vector<float> ranges = simulateScan(room, sensor, spec, kSigma, &rng);
      const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
      // Ahead: the right wall fully, the top and bottom walls partly.
      EXPECT_EQ(lines.size(), 3u) << beams << (clockwise ? " cw" : " ccw");
      for (size_t w : {0u, 1u, 2u}) {  // bottom, right, top
        const Line truth = wallInSensorFrame(room.walls[w], sensor);
        const int i = findLine(lines, truth);
        ASSERT_GE(i, 0) << beams << " wall " << w;
        const Line& estimate = lines[size_t(i)].line;
        const Eigen::Vector2d d = lineDifference(estimate, truth);
        EXPECT_LT(std::abs(d.x()), 5.0 * std::sqrt(estimate.cov(0, 0)) + 1e-4) << beams << " wall " << w;
        EXPECT_LT(std::abs(d.y()), 5.0 * std::sqrt(estimate.cov(1, 1)) + 1e-4) << beams << " wall " << w;
      }
    }
  }
}

TEST(LineExtractor, NoisyLongWallStaysOneLine) {
  World world;
  world.addWall(-20.0, 1.5, 20.0, 1.5);  // a long hallway wall, seen at grazing angles too
  const Pose2D sensor{0.0, 0.0, 0.0};
  const ScanSpec spec = ScanSpec::full(1440);
  std::mt19937 rng(17);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<float> ranges = simulateScan(world, sensor, spec, kSigma, &rng);
    const std::vector<LineSegment> lines = extractLines(makeView(spec, ranges));
    ASSERT_GE(lines.size(), 1u);
    // The dense part near the sensor is one line; far grazing beams may break off.
    Line truth = wallInSensorFrame(world.walls[0], sensor);
    int count = 0;
    for (const LineSegment& s : lines) count += lineMahalanobisSq(s.line, truth) < 50.0 || (std::abs(lineDifference(s.line, truth).x()) < 0.05 && std::abs(lineDifference(s.line, truth).y()) < 0.05);
    EXPECT_EQ(count, int(lines.size()));
    EXPECT_LE(lines.size(), 3u);
  }
}

TEST(LineExtractor, FitLineOnTwoPointsAndDegenerateInput) {
  std::vector<float> ranges = {2.0f, 2.0f};
  ScanView view;
  view.angle_min = 0.0;
  view.angle_increment = 0.1;
  view.range_max = 10.0;
  view.ranges = ranges.data();
  view.size = 2;
  ScanPoints points;
  points.assign(view);
  LineExtractor extractor;
  Line line;
  uint32_t count = 0;
  EXPECT_TRUE(extractor.fitLine(points, 0, 1, &line, &count));
  EXPECT_EQ(count, 2u);
  EXPECT_NEAR(line.alpha, 0.05, 1e-12);
  EXPECT_FALSE(extractor.fitLine(points, 0, 0, &line, &count));  // one point
  std::vector<LineSegment> lines;
  extractor.extract(points, &lines);
  EXPECT_TRUE(lines.empty());  // fewer than min_points
}

}  // namespace
}  // namespace laser_features
