// ScanView validation, circular detection and the counter-clockwise ScanPoints.
#include "laser_features/scan.h"

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace laser_features {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

ScanView viewOf(const std::vector<float>& ranges, double angle_min, double increment) {
  ScanView view;
  view.angle_min = angle_min;
  view.angle_increment = increment;
  view.range_min = 0.1;
  view.range_max = 10.0;
  view.ranges = ranges.data();
  view.size = ranges.size();
  return view;
}

TEST(ClassifyRange, FollowsRep117) {
  EXPECT_EQ(classifyRange(1.0f, 0.1, 10.0), BeamStatus::kValid);
  EXPECT_EQ(classifyRange(kInf, 0.1, 10.0), BeamStatus::kNoReturn);
  EXPECT_EQ(classifyRange(10.5f, 0.1, 10.0), BeamStatus::kNoReturn);
  EXPECT_EQ(classifyRange(-kInf, 0.1, 10.0), BeamStatus::kInvalid);
  EXPECT_EQ(classifyRange(kNaN, 0.1, 10.0), BeamStatus::kInvalid);
  EXPECT_EQ(classifyRange(0.0f, 0.0, 10.0), BeamStatus::kInvalid);
  EXPECT_EQ(classifyRange(-1.0f, 0.0, 10.0), BeamStatus::kInvalid);
  EXPECT_EQ(classifyRange(0.05f, 0.1, 10.0), BeamStatus::kInvalid);
}

TEST(ValidateScan, AcceptsAGoodScan) {
  const std::vector<float> ranges(360, 2.0f);
  EXPECT_EQ(validateScan(viewOf(ranges, -kPi, kTwoPi / 360)), "");
}

TEST(ValidateScan, RefusesEmptyScan) {
  const std::vector<float> ranges;
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, 0.01)), "");
  ScanView null_ranges;
  null_ranges.size = 10;
  null_ranges.angle_increment = 0.01;
  EXPECT_NE(validateScan(null_ranges), "");
}

TEST(ValidateScan, RefusesBadIncrements) {
  const std::vector<float> ranges(10, 2.0f);
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, 0.0)), "");
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, std::nan(""))), "");
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, std::numeric_limits<double>::infinity())), "");
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, 4.0)), "");  // more than pi per beam
  EXPECT_NE(validateScan(viewOf(ranges, std::nan(""), 0.01)), "");
  EXPECT_EQ(validateScan(viewOf(ranges, 0.0, -0.01)), "");  // clockwise scanners are fine
}

TEST(ValidateScan, RefusesMoreThanOneRevolution) {
  const std::vector<float> ranges(1000, 2.0f);
  EXPECT_NE(validateScan(viewOf(ranges, 0.0, kTwoPi / 500)), "");
  const std::vector<float> closing(721, 2.0f);  // angle_max = angle_min + 2 pi: accepted
  EXPECT_EQ(validateScan(viewOf(closing, -kPi, kTwoPi / 720)), "");
}

TEST(ValidateScan, RefusesTooManyBeams) {
  const std::vector<float> ranges(100000, 2.0f);
  const std::string error = validateScan(viewOf(ranges, -kPi, kTwoPi / 100000));
  EXPECT_NE(error.find("max_beams"), std::string::npos) << error;
  EXPECT_EQ(validateScan(viewOf(ranges, -kPi, kTwoPi / 100000), 100000), "");
}

TEST(ValidateScan, RefusesBadRangeLimits) {
  const std::vector<float> ranges(10, 2.0f);
  ScanView view = viewOf(ranges, 0.0, 0.01);
  view.range_min = std::nan("");
  EXPECT_NE(validateScan(view), "");
  view.range_min = 5.0;
  view.range_max = 1.0;
  EXPECT_NE(validateScan(view), "");
}

TEST(ValidateScan, RefusesScansWithoutValidBeams) {
  for (float bad : {kNaN, kInf, -kInf, 0.0f, 0.05f, 20.0f}) {
    const std::vector<float> ranges(100, bad);
    EXPECT_NE(validateScan(viewOf(ranges, 0.0, 0.01)), "") << bad;
  }
}

TEST(ValidateScanHeader, ChecksConsistency) {
  EXPECT_EQ(validateScanHeader(-kPi, kPi - kTwoPi / 720, kTwoPi / 720, 720), "");
  EXPECT_EQ(validateScanHeader(kPi / 2, -kPi / 2, -kPi / 360, 361), "");
  EXPECT_NE(validateScanHeader(1.0, -1.0, 0.01, 201), "");   // angle_max < angle_min, positive increment
  EXPECT_NE(validateScanHeader(-1.0, 1.0, -0.01, 201), "");  // sign mismatch
  EXPECT_NE(validateScanHeader(-1.0, 1.0, 0.01, 100), "");   // 201 ranges expected
  EXPECT_NE(validateScanHeader(-1.0, 1.0, 0.0, 201), "");
  EXPECT_NE(validateScanHeader(-1.0, std::nan(""), 0.01, 201), "");
}

TEST(IsCircularScan, DetectsFullCoverage) {
  const std::vector<float> ranges720(720, 1.0f), ranges361(361, 1.0f), ranges719(719, 1.0f);
  EXPECT_TRUE(isCircularScan(viewOf(ranges720, -kPi, kTwoPi / 720)));
  EXPECT_TRUE(isCircularScan(viewOf(ranges720, 0.3, -kTwoPi / 720)));
  EXPECT_FALSE(isCircularScan(viewOf(ranges361, -kPi / 2, kPi / 360)));
  EXPECT_FALSE(isCircularScan(viewOf(ranges719, -kPi, kTwoPi / 720)));  // one beam short: a gap
}

TEST(ScanPoints, OrdersCounterClockwiseWhateverTheIncrementSign) {
  std::vector<float> ranges(181);
  for (size_t i = 0; i < ranges.size(); ++i) ranges[i] = 1.0f + 0.01f * float(i);
  ScanPoints ccw, cw;
  ccw.assign(viewOf(ranges, -kPi / 2, kPi / 180));
  std::vector<float> reversed(ranges.rbegin(), ranges.rend());
  cw.assign(viewOf(reversed, kPi / 2, -kPi / 180));  // the same scan, clockwise
  ASSERT_EQ(ccw.size(), cw.size());
  EXPECT_DOUBLE_EQ(cw.increment(), kPi / 180);
  for (size_t i = 0; i < ccw.size(); ++i) {
    EXPECT_NEAR((ccw[i].p - cw[i].p).norm(), 0.0, 1e-12);
    EXPECT_NEAR(normalizeAngle(ccw.bearing(i) - cw.bearing(i)), 0.0, 1e-12);
  }
  EXPECT_EQ(cw.sourceIndex(0), 180u);
  EXPECT_NEAR(ccw.bearing(0), -kPi / 2, 1e-12);
  EXPECT_EQ(ccw.indexOfBearing(0.0), 90u);
  EXPECT_EQ(ccw.indexOfBearing(kPi), ccw.size());  // behind a 180 degree scanner
}

TEST(ScanPoints, KeepsOneRevolution) {
  const std::vector<float> ranges(721, 2.0f);
  ScanPoints points;
  points.assign(viewOf(ranges, -kPi, kTwoPi / 720));
  EXPECT_TRUE(points.circular());
  EXPECT_EQ(points.size(), 720u);
  EXPECT_EQ(points.indexOfBearing(kPi - 0.1 * kTwoPi / 720), 0u);  // wraps to the first beam
}

TEST(ScanPoints, MarksInvalidBeams) {
  std::vector<float> ranges = {1.0f, kNaN, kInf, 0.0f, 20.0f, 2.0f};
  ScanPoints points;
  points.assign(viewOf(ranges, 0.0, 0.1));
  EXPECT_EQ(points.numValid(), 2u);
  EXPECT_EQ(points[1].status, BeamStatus::kInvalid);
  EXPECT_EQ(points[2].status, BeamStatus::kNoReturn);
  EXPECT_EQ(points[3].status, BeamStatus::kInvalid);
  EXPECT_EQ(points[4].status, BeamStatus::kNoReturn);
  EXPECT_TRUE(points[2].p.allFinite());
}

}  // namespace
}  // namespace laser_features
