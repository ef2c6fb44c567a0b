// Hallway or room from the free space of one scan.
#include "laser_features/place_classifier.h"

#include "synthetic_scan.h"

#include <gtest/gtest.h>

#include <random>

namespace laser_features {
namespace {

using namespace synthetic;

PlaceEstimate classify(const World& world, const Pose2D& sensor, const ScanSpec& spec, std::mt19937* rng) {
  const std::vector<float> ranges = simulateScan(world, sensor, spec, 0.01, rng);
  ScanPoints points;
  points.assign(makeView(spec, ranges));
  return PlaceClassifier().classify(points, {});
}

World hallway(double width) {
  World world;
  world.addPolygon({{0, 0}, {30, 0}, {30, width}, {0, width}});
  return world;
}

TEST(PlaceClassifier, HallwaysAreHallways) {
  std::mt19937 rng(1);
  for (const double width : {1.5, 2.0, 3.0}) {
    for (const double x : {2.0, 8.0, 15.0, 27.0}) {
      const Pose2D sensor{x, width / 2, 0.7};
      const PlaceEstimate place = classify(hallway(width), sensor, ScanSpec::full(720), &rng);
      EXPECT_EQ(place.type, PlaceType::kHallway) << "width " << width << " x " << x << " W " << place.width
                                                 << " L " << place.length;
      EXPECT_GT(place.confidence, 0.6);
      // The long axis is the hallway's, seen from the sensor.
      EXPECT_NEAR(std::sin(place.axis + sensor.theta), 0.0, 0.1);
      EXPECT_NEAR(place.width, width, 0.3 * width);
    }
  }
}

TEST(PlaceClassifier, RoomsAreRooms) {
  std::mt19937 rng(2);
  const std::vector<std::pair<double, double>> sizes = {{4, 4}, {5, 6}, {7, 5}, {6, 4}};
  for (const auto& [w, h] : sizes) {
    for (const double f : {0.3, 0.5, 0.7}) {
      const Pose2D sensor{f * w, (1 - f) * h + 0.1, 1.0};
      const PlaceEstimate place = classify(rectangularRoom(w, h), sensor, ScanSpec::full(720), &rng);
      EXPECT_EQ(place.type, PlaceType::kRoom) << w << "x" << h << " W " << place.width << " L " << place.length;
      EXPECT_GT(place.confidence, 0.6);
    }
  }
}

TEST(PlaceClassifier, OfficeWithDoorsAndFurnitureIsARoom) {
  std::mt19937 rng(3);
  const PlaceEstimate place = classify(officeScene(), {3.5, 2.5, 0.0}, ScanSpec::full(720), &rng);
  EXPECT_EQ(place.type, PlaceType::kRoom);
}

TEST(PlaceClassifier, HalfScanInAHallway) {
  std::mt19937 rng(4);
  for (const bool clockwise : {true, false}) {
    for (const double heading : {0.0, 1.2, kPi / 2}) {
      const PlaceEstimate place = classify(hallway(2.0), {12.0, 1.0, heading}, ScanSpec::half(361, clockwise), &rng);
      EXPECT_EQ(place.type, PlaceType::kHallway) << heading << " W " << place.width << " L " << place.length;
    }
  }
}

TEST(PlaceClassifier, NoValidBeamIsUnknown) {
  const std::vector<float> ranges(360, std::numeric_limits<float>::quiet_NaN());
  ScanView view;
  view.angle_min = -kPi;
  view.angle_increment = kTwoPi / 360;
  view.range_max = 10.0;
  view.ranges = ranges.data();
  view.size = ranges.size();
  ScanPoints points;
  points.assign(view);
  const PlaceEstimate place = PlaceClassifier().classify(points, {});
  EXPECT_EQ(place.type, PlaceType::kUnknown);
  EXPECT_EQ(place.confidence, 0.0);
}

}  // namespace
}  // namespace laser_features
