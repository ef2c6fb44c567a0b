#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hybrid_slam_rviz/panel_model.h"

using namespace hybrid_slam_rviz;

TEST(PanelModel, StatusLinesSayModePlaceNodeCountsAndTravel) {
  StatusFields s;
  s.mode = "METRIC";
  s.state = "exploring the room";
  s.place = 3;
  s.places = 4;
  s.nodes = 9;
  s.explored = 5;
  s.unexplored = 2;
  s.travel_m = 12.34;
  s.real_time_factor = 21.0;
  const StatusText t = describe(s);
  EXPECT_EQ(t.mode, "METRIC - exploring the room");
  EXPECT_EQ(t.where, "place 3, node - (unconfident)");
  EXPECT_EQ(t.map, "4 places, 9 nodes, openings 5 explored / 2 unexplored");
  EXPECT_EQ(t.travel, "12.3 m travelled, real-time factor 21.0");
}

TEST(PanelModel, BeliefTextComparesTheEntropyWithUMax) {
  EXPECT_EQ(beliefText(0.414, 2.0, true), "U 0.41 of U_max 2.00 nats: confident");
  EXPECT_EQ(beliefText(2.5, 2.0, false), "U 2.50 of U_max 2.00 nats: unconfident");
  EXPECT_EQ(beliefText(std::numeric_limits<double>::quiet_NaN(), 2.0, false), "no belief yet");
}

TEST(PanelModel, PlaceFramesAreNamedByThePrefixAndADecimalId) {
  EXPECT_EQ(placeOfFrame("place_12", "place_"), 12);
  EXPECT_EQ(placeOfFrame("/place_0", "place_"), 0);
  EXPECT_FALSE(placeOfFrame("place_", "place_"));
  EXPECT_FALSE(placeOfFrame("place_1a", "place_"));
  EXPECT_FALSE(placeOfFrame("odom", "place_"));
  EXPECT_FALSE(placeOfFrame("place_99999999999", "place_"));
}

TEST(PanelModel, TheGoalGoesToTheNearestPlaceInThatPlacesFrame) {
  std::vector<PlaceFrame> places = {{0, {0.0, 0.0, 0.0}}, {1, {10.0, 0.0, M_PI / 2}}, {2, {5.0, 8.0, 0.0}}};
  EXPECT_EQ(nearestPlace(places, 9.0, 1.0), 1);
  EXPECT_EQ(nearestPlace(places, 1.0, 1.0), 0);
  EXPECT_EQ(nearestPlace({}, 1.0, 1.0), -1);
  // one metre ahead of place 1's origin along its x axis (the map's +y), facing the map's +x
  const Pose2D g = goalInPlace(places[1].pose, {10.0, 1.0, 0.0});
  EXPECT_NEAR(g.x, 1.0, 1e-12);
  EXPECT_NEAR(g.y, 0.0, 1e-12);
  EXPECT_NEAR(g.theta, -M_PI / 2, 1e-12);
}
