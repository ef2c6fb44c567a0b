// Vertical edges and colour patches of synthetic panoramas (with the camera's noise), the laser's
// features around the camera, and the fingerprint's order.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fingerprint/fingerprint.h"
#include "fingerprint/visual_features.h"

using namespace fingerprint;

namespace {

const PanoramaModel kModel;  // 720 x 120, 60 deg up and down

// A panorama whose wall band (every row here) has colour `color(c)` in column c, plus Gaussian noise.
template <typename Color>
cv::Mat panorama(Color color, double noise = 2.0, uint32_t seed = 1) {
  cv::Mat img(kModel.height, kModel.width, CV_8UC3);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, noise);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c) {
      const cv::Vec3d v = color(c);
      for (int k = 0; k < 3; ++k) img.at<cv::Vec3b>(r, c)[k] = cv::saturate_cast<uint8_t>(v[k] + (noise > 0 ? n(rng) : 0.0));
    }
  return img;
}

std::vector<Feature> ofType(const std::vector<Feature>& all, FeatureType t) {
  std::vector<Feature> out;
  for (const Feature& f : all)
    if (f.type == t) out.push_back(f);
  return out;
}

double angleDiff(double a, double b) { return std::remainder(a - b, 2 * M_PI); }

}  // namespace

TEST(VisualFeatures, AGreyWallWithNoiseHasNoEdgeAndNoPatch) {
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  ASSERT_TRUE(x.extract(panorama([](int) { return cv::Vec3d(128, 128, 125); }), kModel, &f));
  EXPECT_TRUE(f.empty());
}

TEST(VisualFeatures, TwoWallsMeetAtTwoEdgesAndMakeTwoPatches) {
  // Columns 0-299 red, 300-719 blue: edges between 299 and 300, and between 719 and 0.
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  ASSERT_TRUE(x.extract(panorama([](int c) { return c < 300 ? cv::Vec3d(200, 60, 50) : cv::Vec3d(50, 60, 200); }),
                        kModel, &f));
  const auto edges = ofType(f, FeatureType::VerticalEdge);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_NEAR(angleDiff(edges[0].bearing, kModel.bearingAt(300.0)), 0.0, 1e-9);
  EXPECT_NEAR(std::abs(angleDiff(edges[1].bearing, M_PI)), 0.0, 1e-9);  // the seam behind
  EXPECT_NEAR(edges[0].sigma, 1.0 / (kModel.fx * std::sqrt(12.0)), 1e-12);
  EXPECT_GT(edges[0].strength, 0.99);
  const auto patches = ofType(f, FeatureType::ColorPatch);
  ASSERT_EQ(patches.size(), 2u);
  EXPECT_EQ(patches[0].hue_bin, 0);  // red: hue 4 deg
  EXPECT_NEAR(angleDiff(patches[0].bearing, kModel.bearingAt(150.0)), 0.0, 1e-9);
  EXPECT_NEAR(patches[0].width, 300.0 / kModel.fx, 1e-9);
  EXPECT_EQ(patches[1].hue_bin, 7);  // blue: hue 236 deg, bin 210-240
  EXPECT_NEAR(patches[0].color[0], 200, 1);
}

TEST(VisualFeatures, ADoorFrameIsTwoEdgesButTooNarrowForAPatch) {
  // A 4-column brown frame (0.035 rad) on a pale wall.
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  ASSERT_TRUE(x.extract(panorama([](int c) { return c >= 400 && c < 404 ? cv::Vec3d(110, 75, 45) : cv::Vec3d(225, 225, 215); }),
                        kModel, &f));
  const auto edges = ofType(f, FeatureType::VerticalEdge);
  ASSERT_EQ(edges.size(), 2u);
  EXPECT_NEAR(angleDiff(edges[0].bearing, kModel.bearingAt(400.0)), 0.0, 1e-9);
  EXPECT_NEAR(angleDiff(edges[1].bearing, kModel.bearingAt(404.0)), 0.0, 1e-9);
  EXPECT_TRUE(ofType(f, FeatureType::ColorPatch).empty());
}

TEST(VisualFeatures, ShadingAlongAWallIsNoEdge) {
  // Lambert shading changes a wall's brightness by a fraction of a level per column.
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  ASSERT_TRUE(x.extract(panorama([](int c) { return cv::Vec3d(90, 160, 90) * (0.5 + 0.5 * std::sin(c * M_PI / 720.0)); }),
                        kModel, &f));
  EXPECT_TRUE(ofType(f, FeatureType::VerticalEdge).empty());
}

TEST(VisualFeatures, TheEdgeThresholdIsTheCamerasNoise) {
  // A 20-level step: with sigma 2 the threshold is 6 * sqrt(2) * 2 = 17 levels - an edge; with sigma
  // 4 (34 levels) it is noise.
  auto step = [](int c) { return c < 200 ? cv::Vec3d(120, 120, 120) : cv::Vec3d(140, 140, 140); };
  VisualFeatureParams p;
  std::vector<Feature> f;
  VisualFeatureExtractor quiet(p);
  ASSERT_TRUE(quiet.extract(panorama(step, 0.0), kModel, &f));
  EXPECT_EQ(ofType(f, FeatureType::VerticalEdge).size(), 2u);
  p.image_noise_stddev = 4.0;
  VisualFeatureExtractor noisy(p);
  f.clear();
  ASSERT_TRUE(noisy.extract(panorama(step, 0.0), kModel, &f));
  EXPECT_TRUE(ofType(f, FeatureType::VerticalEdge).empty());
}

TEST(VisualFeatures, OnlyTheWallBandCounts) {
  // A step in the rows above the band only (a ceiling's light) makes no edge.
  cv::Mat img = panorama([](int) { return cv::Vec3d(128, 128, 128); }, 0.0);
  for (int r = 0; r < 20; ++r)
    for (int c = 100; c < 200; ++c) img.at<cv::Vec3b>(r, c) = cv::Vec3b(255, 255, 255);
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  ASSERT_TRUE(x.extract(img, kModel, &f));
  EXPECT_TRUE(f.empty());
}

TEST(VisualFeatures, AnImageThatIsNotThePanoramaIsRefused) {
  VisualFeatureExtractor x;
  std::vector<Feature> f;
  std::string why;
  EXPECT_FALSE(x.extract(cv::Mat(100, 720, CV_8UC3, cv::Scalar(0)), kModel, &f, &why));
  EXPECT_NE(why.find("720 x 100"), std::string::npos);
  EXPECT_FALSE(x.extract(cv::Mat(120, 720, CV_8UC1, cv::Scalar(0)), kModel, &f, &why));
  PanoramaModel pinhole = kModel;
  pinhole.fx = 500.0;  // a pinhole camera's: its columns do not go round
  EXPECT_FALSE(x.extract(panorama([](int) { return cv::Vec3d(0, 0, 0); }), pinhole, &f, &why));
  EXPECT_NE(why.find("not a panorama"), std::string::npos);
  EXPECT_TRUE(f.empty());
  VisualFeatureParams bad;
  bad.hue_bins = 1;
  EXPECT_FALSE(VisualFeatureExtractor::validate(bad));
  EXPECT_THROW(VisualFeatureExtractor{bad}, std::invalid_argument);
}

TEST(Fingerprint, LaserFeaturesAreSeenFromTheCamera) {
  const Pose2 laser{0.05, 0.0, 0.0};  // the laser 5 cm ahead of the camera
  Eigen::Matrix2d cov = Eigen::Matrix2d::Identity() * 1e-4;  // 1 cm
  const Feature ahead = laserCorner(laser, Eigen::Vector2d(1.95, 0.0), cov, 0.9);
  EXPECT_EQ(ahead.type, FeatureType::LaserCorner);
  EXPECT_NEAR(ahead.bearing, 0.0, 1e-12);
  EXPECT_NEAR(ahead.sigma, 0.01 / 2.0, 1e-9);  // 1 cm across at 2 m
  const Feature left = laserCorner(laser, Eigen::Vector2d(-0.05, 2.0), cov, 0.9);
  EXPECT_NEAR(left.bearing, M_PI / 2, 1e-12);
  const Feature door = laserOpening(laser, Eigen::Vector2d(-2.05, 0.0), 0.9, true, 0.8);
  EXPECT_EQ(door.type, FeatureType::LaserDoor);
  EXPECT_NEAR(std::abs(door.bearing), M_PI, 1e-12);
  EXPECT_NEAR(door.sigma, 2.0 * std::atan(0.45 / 2.0) / std::sqrt(12.0), 1e-9);  // 2 m from the camera
  std::vector<Feature> all{door, left, ahead};
  sortByBearing(&all);
  EXPECT_EQ(all[0].type, FeatureType::LaserCorner);
  EXPECT_NEAR(all[0].bearing, 0.0, 1e-12);
  EXPECT_NEAR(all[1].bearing, M_PI / 2, 1e-12);
  EXPECT_EQ(all[2].type, FeatureType::LaserDoor);
}
