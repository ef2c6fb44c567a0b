// Fingerprint matching by global alignment: rotations, occlusions, noise, kinds, and telling places
// apart.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fingerprint/fingerprint.h"
#include "fingerprint/matcher.h"

using namespace fingerprint;

namespace {

Feature feature(FeatureType t, double bearing, double sigma = 0.02, int hue = -1) {
  Feature f;
  f.type = t;
  f.bearing = std::remainder(bearing, 2 * M_PI);
  f.sigma = sigma;
  f.hue_bin = hue;
  return f;
}

std::vector<Feature> turned(std::vector<Feature> fp, double rotation) {
  for (Feature& f : fp) f.bearing = std::remainder(f.bearing + rotation, 2 * M_PI);
  sortByBearing(&fp);
  return fp;
}

// A place's fingerprint: 6-14 features of random kinds and bearings.
std::vector<Feature> randomPlace(std::mt19937& rng) {
  std::uniform_int_distribution<int> count(6, 14), kind(1, 5), hue(0, 11);
  std::uniform_real_distribution<double> bearing(-M_PI, M_PI);
  std::vector<Feature> fp;
  const int n = count(rng);
  for (int k = 0; k < n; ++k) {
    const auto t = FeatureType(kind(rng));
    fp.push_back(feature(t, bearing(rng), 0.02, t == FeatureType::ColorPatch ? hue(rng) : -1));
  }
  sortByBearing(&fp);
  return fp;
}

}  // namespace

TEST(Matcher, AFingerprintMatchesItselfAtNoCost) {
  const std::vector<Feature> a{feature(FeatureType::VerticalEdge, -2.0), feature(FeatureType::LaserCorner, -0.5),
                               feature(FeatureType::ColorPatch, 0.3, 0.1, 4), feature(FeatureType::LaserDoor, 1.9)};
  const Match m = FingerprintMatcher().match(a, a);
  EXPECT_NEAR(m.cost, 0.0, 1e-12);
  EXPECT_NEAR(m.rotation, 0.0, 1e-12);
  EXPECT_EQ(m.pairs, 4);
  EXPECT_EQ(m.gaps, 0);
}

TEST(Matcher, TheRobotsTurnIsTheRotationEvenAcrossTheBack) {
  // Features at +-3.1 rad straddle the back of the circle; the robot turned 0.7 rad.
  const std::vector<Feature> a{feature(FeatureType::VerticalEdge, -3.1), feature(FeatureType::LaserCorner, -1.0),
                               feature(FeatureType::VerticalEdge, 0.4), feature(FeatureType::LaserCorner, 3.1)};
  const std::vector<Feature> b = turned(a, -0.7);  // the world turned the other way in the robot's frame
  const Match m = FingerprintMatcher().match(a, b);
  EXPECT_NEAR(m.rotation, -0.7, 1e-9);
  EXPECT_NEAR(m.cost, 0.0, 1e-9);
  EXPECT_EQ(m.pairs, 4);
}

TEST(Matcher, AnOccludedFeatureCostsAGap) {
  std::vector<Feature> a{feature(FeatureType::VerticalEdge, -2.0), feature(FeatureType::LaserCorner, -0.5),
                         feature(FeatureType::VerticalEdge, 0.6), feature(FeatureType::LaserDoor, 1.9)};
  std::vector<Feature> b = a;
  b.erase(b.begin() + 2);
  const FingerprintMatcher matcher;
  const Match m = matcher.match(a, b);
  EXPECT_NEAR(m.cost, matcher.params().gap_cost, 1e-9);
  EXPECT_EQ(m.pairs, 3);
  EXPECT_EQ(m.gaps, 1);
}

TEST(Matcher, OnlyFeaturesOfOneKindPairAndPatchesOfOneHue) {
  const FingerprintMatcher matcher;
  const double gap = matcher.params().gap_cost;
  EXPECT_NEAR(matcher.match({feature(FeatureType::VerticalEdge, 0.0)}, {feature(FeatureType::LaserCorner, 0.0)}).cost,
              2 * gap, 1e-12);
  EXPECT_NEAR(matcher.match({feature(FeatureType::ColorPatch, 0.0, 0.1, 3)}, {feature(FeatureType::ColorPatch, 0.0, 0.1, 4)}).cost,
              2 * gap, 1e-12);
  EXPECT_NEAR(matcher.match({feature(FeatureType::ColorPatch, 0.0, 0.1, 3)}, {feature(FeatureType::ColorPatch, 0.0, 0.1, 3)}).cost,
              0.0, 1e-12);
  EXPECT_NEAR(matcher.match({}, {}).cost, 0.0, 1e-12);
}

TEST(Matcher, APairCostsItsBearingDifferenceInStandardDeviations) {
  // 0.04 rad apart, each bearing 0.02 rad: (0.04)^2 / 2 (2 * 0.02^2) = 1.
  const FingerprintMatcher matcher;
  const Match m = matcher.align({feature(FeatureType::LaserCorner, 0.0), feature(FeatureType::VerticalEdge, 1.0)},
                                {feature(FeatureType::LaserCorner, 0.04), feature(FeatureType::VerticalEdge, 1.0)}, 0.0);
  EXPECT_NEAR(m.cost, 1.0, 1e-9);
  EXPECT_EQ(m.pairs, 2);
}

TEST(Matcher, APlaceSeenAgainIsTheBestMatchOfTwentyPlaces) {
  // Twenty places; each seen again turned by a random heading, with bearing noise of the features'
  // own sigma, one feature occluded and one new: the least-cost stored place is the right one.
  std::mt19937 rng(7);
  std::vector<std::vector<Feature>> places;
  for (int k = 0; k < 20; ++k) places.push_back(randomPlace(rng));
  std::uniform_real_distribution<double> heading(-M_PI, M_PI), bearing(-M_PI, M_PI);
  std::normal_distribution<double> noise(0.0, 0.02);
  const FingerprintMatcher matcher;
  int right = 0;
  for (int k = 0; k < 20; ++k) {
    std::vector<Feature> seen = places[k];
    for (Feature& f : seen) f.bearing += noise(rng);
    seen.erase(seen.begin() + int(rng() % seen.size()));
    seen.push_back(feature(FeatureType::LaserCorner, bearing(rng)));
    const double turn = heading(rng);
    seen = turned(seen, turn);
    int best = -1;
    double best_cost = 1e18;
    for (int p = 0; p < 20; ++p) {
      const Match m = matcher.match(seen, places[p]);
      if (m.cost < best_cost) best_cost = m.cost, best = p;
    }
    if (best == k) {
      ++right;
      EXPECT_NEAR(std::remainder(matcher.match(seen, places[k]).rotation + turn, 2 * M_PI), 0.0, 0.05);
    }
  }
  EXPECT_GE(right, 19);
}
