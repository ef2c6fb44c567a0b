// Places: creation (origin at the robot's pose on entry), activation, closing, only the active place
// updated; doors; relocation on entering a known place through a door, its success in the right
// room and its failure (nothing fused) in a wrong room or with only parallel lines; both again after
// the places were saved compact (marginals only) and loaded.
#include "ekf_local_map/persistence.h"
#include "ekf_local_map/place_maps.h"

#include "simulated_room.h"

#include <gtest/gtest.h>

#include <random>

namespace ekf_local_map {
namespace {

using laser_features::compose;
using laser_features::normalizeAngle;
using namespace testing_support;

const Pose2D kSensorMount{0.12, -0.03, 0.05};

/// Drives a short arc in the office room of the active place; returns the true pose at the end.
Pose2D mapOfficeRoom(StochasticMap* map, std::mt19937* rng, Pose2D truth = {0, 0, 0}) {
  const OdometryNoise noise = testOdometryNoise();
  map->update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, nullptr);
  for (int step = 0; step < 40; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0625);
    truth = compose(truth, u);
    map->predict(noisyIncrement(u, noise, rng), noise.covariance(u));
    map->update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, nullptr);
  }
  return truth;
}

TEST(PlaceMaps, CreateActivateClose) {
  PlaceMaps places(testParams());
  EXPECT_EQ(places.active(), nullptr);
  const uint32_t a = places.createPlace({10.0, 5.0, 0.3});
  ASSERT_NE(places.active(), nullptr);
  EXPECT_EQ(places.activeId(), a);
  // The place frame is the robot's pose on entry.
  EXPECT_EQ(places.active()->robotPose().x, 0.0);
  EXPECT_EQ(places.active()->robotCovariance(), Eigen::Matrix3d::Zero());
  EXPECT_EQ(places.place(a)->display_pose.x, 10.0);

  std::mt19937 rng(1);
  mapOfficeRoom(places.active(), &rng);
  const size_t lines_a = places.place(a)->map.numLines();
  EXPECT_EQ(lines_a, officeRoom().size());

  const uint32_t b = places.createPlace({20.0, 5.0, 0.0});
  EXPECT_NE(a, b);
  EXPECT_EQ(places.activeId(), b);
  EXPECT_EQ(places.active()->numLines(), 0u);
  places.active()->update(observeAll(otherRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  EXPECT_EQ(places.place(b)->map.numLines(), otherRoom().size());
  EXPECT_EQ(places.place(a)->map.numLines(), lines_a);  // only the active place changes

  places.close();
  EXPECT_EQ(places.active(), nullptr);
  EXPECT_FALSE(places.activeId().has_value());
  EXPECT_TRUE(places.activate(a));
  EXPECT_EQ(places.active(), &places.place(a)->map);
  EXPECT_FALSE(places.activate(99));
  EXPECT_EQ(places.activeId(), a);
  EXPECT_EQ(places.placeIds(), (std::vector<uint32_t>{a, b}));
}

TEST(PlaceMaps, DoorsAreStoredPerPlace) {
  PlaceMaps places(testParams());
  const uint32_t a = places.createPlace({});
  EXPECT_TRUE(places.addDoor(a, 3, {1.0, -1.5, 0.5 * kPi}, Eigen::Matrix3d::Identity() * 1e-4));
  EXPECT_FALSE(places.addDoor(a + 1, 3, {1.0, -1.5, 0.0}, Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(places.addDoor(a, 4, {std::nan(""), 0.0, 0.0}, Eigen::Matrix3d::Identity()));
  ASSERT_EQ(places.place(a)->doors.size(), 1u);
  EXPECT_EQ(places.place(a)->doors.at(3).pose.y, -1.5);

  // A door at the robot: its covariance is the robot's, propagated.
  places.active()->predict({0.5, 0.0, 0.1}, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  ASSERT_TRUE(places.addDoorAtRobot(5, {0.3, 0.0, 0.0}));
  const Door& door = places.place(a)->doors.at(5);
  EXPECT_NEAR(door.pose.x, 0.5 + 0.3 * std::cos(0.1), 1e-12);
  EXPECT_GT(door.cov(1, 1), 1e-4);  // heading uncertainty moves the door sideways
  places.close();
  EXPECT_FALSE(places.addDoorAtRobot(6, {}));
}

TEST(Relocation, AtADoorOfTheRightRoomSucceeds) {
  std::mt19937 rng(2);
  PlaceMaps places(testParams());
  const uint32_t office = places.createPlace({});
  const Pose2D truth_at_door = mapOfficeRoom(places.active(), &rng);
  ASSERT_TRUE(places.addDoorAtRobot(1, {0.0, 0.0, 0.0}));  // the robot stands in the door
  places.close();  // topological mode: the office's map is kept

  // Later the robot comes back through the same door, 0.3 m further in and 10 degrees turned.
  const Pose2D offset{0.3, 0.0, 0.17};
  const Pose2D truth = compose(truth_at_door, offset);
  // The topological layer's estimate of the offset is rough.
  const Eigen::Matrix3d offset_cov = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.08 * 0.08).asDiagonal();
  ASSERT_TRUE(places.relocateAtDoor(office, 1, {0.35, -0.05, 0.22}, offset_cov));
  EXPECT_EQ(places.activeId(), office);
  StochasticMap& map = *places.active();
  EXPECT_TRUE(map.relocationPending());
  const size_t lines = map.numLines();

  UpdateReport report;
  map.update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
  ASSERT_TRUE(report.relocation_attempted);
  EXPECT_TRUE(report.relocation.success()) << toString(report.relocation.verdict);
  EXPECT_GE(report.relocation.matched, 5u);
  EXPECT_TRUE(report.fused);
  EXPECT_FALSE(map.relocationPending());
  EXPECT_LT(positionError(map.robotPose(), truth), 0.01);
  EXPECT_LT(std::abs(normalizeAngle(map.robotPose().theta - truth.theta)), 0.005);
  EXPECT_LT(map.robotNees(truth), 16.0);
  EXPECT_EQ(map.numLines(), lines);
  // and the filter carries on normally.
  map.update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_FALSE(report.relocation_attempted);
  EXPECT_EQ(report.matched, officeRoom().size());
}

// A room with two doors is one place: the second door, seen from inside and found from the hallway
// after the place was closed, is stored in the closed place at its pose there (with the place's last
// robot covariance), and the robot relocates at it as at the first.
TEST(Relocation, AtASecondDoorStoredAfterThePlaceWasClosedSucceeds) {
  std::mt19937 rng(4);
  PlaceMaps places(testParams());
  const uint32_t office = places.createPlace({});
  const Pose2D end = mapOfficeRoom(places.active(), &rng);
  const Eigen::Matrix3d last_cov = places.active()->robotCovariance();
  places.close();
  const Pose2D second_door = compose(end, Pose2D{0.5, 0.2, 0.3});
  EXPECT_FALSE(places.addDoorInPlace(office + 1, 7, second_door)) << "no such place";
  EXPECT_FALSE(places.addDoorInPlace(office, 7, {std::nan(""), 0.0, 0.0}));
  ASSERT_TRUE(places.addDoorInPlace(office, 7, second_door));
  EXPECT_FALSE(places.activeId().has_value()) << "storing a door activates nothing";
  const Door& door = places.place(office)->doors.at(7);
  EXPECT_EQ(door.pose.x, second_door.x);
  EXPECT_TRUE(door.cov.isApprox(last_cov));

  const Pose2D offset{-0.4, 0.1, 0.1};
  const Eigen::Matrix3d offset_cov = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.08 * 0.08).asDiagonal();
  ASSERT_TRUE(places.relocateAtDoor(office, 7, {-0.35, 0.05, 0.13}, offset_cov));
  const Pose2D truth = compose(second_door, offset);
  UpdateReport report;
  places.active()->update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, &report);
  ASSERT_TRUE(report.relocation_attempted);
  EXPECT_TRUE(report.relocation.success()) << toString(report.relocation.verdict);
  EXPECT_LT(positionError(places.active()->robotPose(), truth), 0.02);
}

// The office mapped from its door and closed, with door 1 stored where the robot began; its id.
uint32_t closedOfficeWithDoor(PlaceMaps* places, std::mt19937* rng) {
  const uint32_t office = places->createPlace({});
  mapOfficeRoom(places->active(), rng);
  EXPECT_TRUE(places->addDoor(office, 1, {0.0, 0.0, 0.0}, Eigen::Matrix3d::Identity() * 1e-6));
  places->close();
  return office;
}

TEST(Relocation, InTheWrongRoomFailsAndFusesNothing) {
  std::mt19937 rng(3);
  PlaceMaps places(testParams());
  const uint32_t office = closedOfficeWithDoor(&places, &rng);

  // The robot believes it enters the office, but it is in the other room.
  ASSERT_TRUE(places.relocateAtDoor(office, 1, {0.0, 0.0, 0.0}, Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal()));
  StochasticMap& map = *places.active();
  std::vector<MapLine> lines_before;
  for (size_t i = 0; i < map.numLines(); ++i) lines_before.push_back(map.line(i));
  const Eigen::MatrixXd P = map.covariance();
  const Eigen::VectorXd x = map.state();

  UpdateReport report;
  for (int scan = 0; scan < 5; ++scan) {
    map.update(observeAll(otherRoom(), {0.0, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, &report);
    ASSERT_TRUE(report.relocation_attempted);
    EXPECT_FALSE(report.relocation.success())
        << "scan " << scan << ": " << report.relocation.matched << " matches, joint NIS "
        << report.relocation.joint_nis;
    EXPECT_FALSE(report.fused);
    EXPECT_EQ(report.new_lines, 0u);
    EXPECT_TRUE(map.relocationPending());
    EXPECT_EQ(map.state(), x);  // the office's map is not corrupted
    EXPECT_EQ(map.covariance(), P);
  }
  std::printf("wrong room: %s (%u matches, joint NIS %.1f, bound %.1f)\n", toString(report.relocation.verdict),
              report.relocation.matched, report.relocation.joint_nis, report.relocation.joint_nis_bound);
}

TEST(Relocation, ParallelLinesOnlyDoNotFixThePose) {
  std::mt19937 rng(4);
  // A corridor-like place: two long walls and a shelf, all parallel.
  const std::vector<TrueSegment> corridor = {
      {{-3.0, -1.0}, {5.0, -1.0}}, {{-3.0, 1.2}, {5.0, 1.2}}, {{0.0, 0.8}, {2.0, 0.8}}};
  StochasticMap map(testParams());
  map.update(observeAll(corridor, {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  ASSERT_EQ(map.numLines(), 3u);
  map.relocate({0.5, 0.0, 0.0}, Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal());
  UpdateReport report;
  map.update(observeAll(corridor, {0.5, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, &report);
  EXPECT_EQ(report.relocation.matched, 3u);
  EXPECT_EQ(report.relocation.verdict, RelocationResult::Verdict::kParallelLines);
  EXPECT_FALSE(report.fused);
}

TEST(Relocation, TooFewLinesFails) {
  std::mt19937 rng(5);
  StochasticMap map(testParams());
  map.update(observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  map.relocate({0.0, 0.0, 0.0}, Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal());
  std::vector<LineSegment> two = observeAll(officeRoom(), {0, 0, 0}, kSensorMount, &rng);
  two.resize(2);
  UpdateReport report;
  map.update(two, kSensorMount, &report);
  EXPECT_EQ(report.relocation.verdict, RelocationResult::Verdict::kTooFewMatches);
  EXPECT_TRUE(map.relocationPending());
}

/// The places as the node has them after load_map: saved (compact unless `options` say otherwise)
/// and loaded into fresh maps.
PlaceMaps reloaded(const PlaceMaps& places, const PlacesSaveOptions& options = PlacesSaveOptions()) {
  PlaceMaps loaded(testParams());
  const IoResult result = decodePlaces(encodePlaces(places, options), "reloaded", &loaded);
  EXPECT_TRUE(result.ok) << result.error;
  return loaded;
}

/// What one relocation did: the verdict, the robot's errors against the truth, the second scan's matches.
struct RelocationOutcome {
  RelocationResult relocation;
  double position_error = 0.0, heading_error = 0.0, nees = 0.0;
  uint32_t matched_after = 0;
};

/// AtADoorOfTheRightRoomSucceeds's relocation, in `places` as they are.
RelocationOutcome relocateInOffice(PlaceMaps* places, uint32_t office, const Pose2D& truth_at_door,
                                   std::mt19937* rng) {
  const Pose2D truth = compose(truth_at_door, {0.3, 0.0, 0.17});
  const Eigen::Matrix3d offset_cov = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.08 * 0.08).asDiagonal();
  RelocationOutcome out;
  if (!places->relocateAtDoor(office, 1, {0.35, -0.05, 0.22}, offset_cov)) return out;
  StochasticMap& map = *places->active();
  UpdateReport report;
  map.update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, &report);
  out.relocation = report.relocation;
  out.position_error = positionError(map.robotPose(), truth);
  out.heading_error = std::abs(normalizeAngle(map.robotPose().theta - truth.theta));
  out.nees = map.robotNees(truth);
  map.update(observeAll(officeRoom(), truth, kSensorMount, rng), kSensorMount, &report);
  out.matched_after = report.matched;
  return out;
}

TEST(Relocation, AfterLoadingACompactMapSucceeds) {
  // The office mapped with 20 seeds; each map saved compact and loaded (P block-diagonal), and the
  // same map saved whole and loaded, then the same relocation in both.
  double nees_compact = 0.0, nees_full = 0.0, nis_compact = 0.0, nis_full = 0.0;
  const int seeds = 20;
  for (int seed = 0; seed < seeds; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 rng(100 + seed);
    PlaceMaps places(testParams());
    const uint32_t office = places.createPlace({});
    const Pose2D truth_at_door = mapOfficeRoom(places.active(), &rng);
    ASSERT_TRUE(places.addDoorAtRobot(1, {0.0, 0.0, 0.0}));
    places.close();

    PlaceMaps compact = reloaded(places);
    ASSERT_EQ(compact.place(office)->map.numLines(), officeRoom().size());
    ASSERT_TRUE(compact.place(office)->map.lineCrossCovariance(1, 0).isZero(0.0));  // the compact record was read
    std::mt19937 rng_compact(200 + seed), rng_full(200 + seed);  // the same scans for both
    const RelocationOutcome c = relocateInOffice(&compact, office, truth_at_door, &rng_compact);
    PlaceMaps full = reloaded(places, PlacesSaveOptions{true});
    const RelocationOutcome f = relocateInOffice(&full, office, truth_at_door, &rng_full);

    EXPECT_TRUE(c.relocation.success()) << toString(c.relocation.verdict) << ", joint NIS " << c.relocation.joint_nis;
    EXPECT_GE(c.relocation.matched, 5u);
    EXPECT_LT(c.position_error, 0.01);
    EXPECT_LT(c.heading_error, 0.005);
    EXPECT_LT(c.nees, 16.3);  // chi^2_3 at 0.999
    EXPECT_EQ(c.matched_after, officeRoom().size());  // and the filter carries on
    EXPECT_TRUE(f.relocation.success());
    nees_compact += c.nees / seeds;
    nees_full += f.nees / seeds;
    nis_compact += c.relocation.joint_nis / seeds;
    nis_full += f.relocation.joint_nis / seeds;
  }
  // Printed for the record: the mean robot NEES after relocation (3 when consistent) and the mean
  // joint NIS of the relocation (2 x 7 = 14 when consistent), compact vs whole map.
  std::printf("after relocation, mean over %d seeds: robot NEES %.2f compact, %.2f full; joint NIS %.2f compact, "
              "%.2f full\n", seeds, nees_compact, nees_full, nis_compact, nis_full);
}

TEST(Relocation, AfterLoadingACompactMapTheWrongRoomStillFails) {
  std::mt19937 rng(3);
  PlaceMaps places(testParams());
  const uint32_t office = closedOfficeWithDoor(&places, &rng);
  PlaceMaps loaded = reloaded(places);
  ASSERT_TRUE(loaded.relocateAtDoor(office, 1, {0.0, 0.0, 0.0}, Eigen::Vector3d(0.04, 0.04, 0.01).asDiagonal()));
  StochasticMap& map = *loaded.active();
  const Eigen::VectorXd x = map.state();
  UpdateReport report;
  for (int scan = 0; scan < 5; ++scan) {
    map.update(observeAll(otherRoom(), {0.0, 0.0, 0.0}, kSensorMount, &rng), kSensorMount, &report);
    ASSERT_TRUE(report.relocation_attempted);
    EXPECT_FALSE(report.relocation.success()) << "scan " << scan;
    EXPECT_FALSE(report.fused);
    EXPECT_EQ(map.state(), x);
  }
}

TEST(PlaceMaps, RelocateAtAnUnknownDoorChangesNothing) {
  PlaceMaps places(testParams());
  const uint32_t a = places.createPlace({});
  places.close();
  EXPECT_FALSE(places.relocateAtDoor(a, 9, {}, Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(places.relocateAtDoor(a + 7, 0, {}, Eigen::Matrix3d::Identity()));
  EXPECT_FALSE(places.activeId().has_value());
  EXPECT_FALSE(places.place(a)->map.relocationPending());
}

}  // namespace
}  // namespace ekf_local_map
