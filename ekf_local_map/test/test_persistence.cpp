// Saving and loading places: an exact round trip; refusal of truncated files, flipped bytes, a bad
// magic line, a newer version, non-finite numbers and non-PSD covariances (with a valid checksum),
// always leaving the maps in memory as they were; atomic writes; storage size per place and per m^2.
#include "laser_features/file_io.h"
#include "ekf_local_map/persistence.h"

#include "simulated_room.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>

namespace ekf_local_map {
namespace {

using laser_features::compose;
using namespace testing_support;

const Pose2D kSensorMount{0.12, -0.03, 0.05};

/// Two mapped places with doors.
PlaceMaps twoPlaces() {
  std::mt19937 rng(5);
  PlaceMaps places(testParams());
  const OdometryNoise noise = testOdometryNoise();
  const uint32_t a = places.createPlace({12.0, -3.0, 0.4});
  Pose2D truth{0, 0, 0};
  for (int step = 0; step < 30; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0625);
    truth = compose(truth, u);
    places.active()->predict(noisyIncrement(u, noise, &rng), noise.covariance(u));
    places.active()->update(observeAll(officeRoom(), truth, kSensorMount, &rng), kSensorMount, nullptr);
  }
  places.addDoorAtRobot(1, {0.2, 0.0, 0.0});
  places.addDoor(a, 2, {3.5, 1.0, kPi}, Eigen::Vector3d(1e-3, 2e-3, 1e-4).asDiagonal());
  const uint32_t b = places.createPlace({30.0, 2.0, -1.2});
  places.active()->update(observeAll(otherRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
  places.addDoor(b, 1, {-2.0, 0.5, 0.0}, Eigen::Matrix3d::Identity() * 1e-4);
  places.close();
  return places;
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "ekf_local_map_" + std::to_string(::getpid()) + "_" + name;
}

std::string readFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream s;
  s << file.rdbuf();
  return s.str();
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << bytes;
}

bool exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

/// Replaces the trailing CRC so that a deliberately altered body passes the checksum.
std::string withValidChecksum(std::string bytes) {
  const uint32_t crc = laser_features::crc32(bytes.data(), bytes.size() - 4);
  for (int b = 0; b < 4; ++b) bytes[bytes.size() - 4 + size_t(b)] = char((crc >> (8 * b)) & 0xffu);
  return bytes;
}

/// Byte offset of the first line's alpha in place #0: after the header, counts, place fields.
size_t firstLineOffset(const std::string& bytes) {
  const size_t body = bytes.find('\n', bytes.find('\n') + 1) + 1;
  return body + 8 /* count, next id */ + 4 + 24 + 4 + 4 + 4 + 24 /* id, display, flags, n, d, robot */;
}

void expectSamePlaces(const PlaceMaps& a, const PlaceMaps& b) {
  ASSERT_EQ(a.placeIds(), b.placeIds());
  EXPECT_EQ(a.nextId(), b.nextId());
  for (const uint32_t id : a.placeIds()) {
    const Place& p = *a.place(id);
    const Place& q = *b.place(id);
    EXPECT_EQ(p.display_pose.x, q.display_pose.x);
    EXPECT_EQ(p.display_pose.theta, q.display_pose.theta);
    EXPECT_EQ(p.map.state(), q.map.state());
    EXPECT_EQ(p.map.covariance(), q.map.covariance());
    ASSERT_EQ(p.map.numLines(), q.map.numLines());
    for (size_t i = 0; i < p.map.numLines(); ++i) {
      EXPECT_EQ(p.map.line(i).extent_start, q.map.line(i).extent_start);
      EXPECT_EQ(p.map.line(i).extent_end, q.map.line(i).extent_end);
    }
    ASSERT_EQ(p.doors.size(), q.doors.size());
    for (const auto& door : p.doors) {
      EXPECT_EQ(door.second.pose.y, q.doors.at(door.first).pose.y);
      EXPECT_EQ(door.second.cov, q.doors.at(door.first).cov);
    }
  }
}

TEST(Persistence, RoundTripIsExact) {
  const PlaceMaps places = twoPlaces();
  const std::string path = tempPath("round_trip.places");
  const IoResult saved = savePlaces(places, path);
  ASSERT_TRUE(saved) << saved.error;
  EXPECT_FALSE(exists(path + ".tmp"));
  EXPECT_EQ(readFile(path).rfind("hybrid_slam_places\nversion 1\n", 0), 0u);

  PlaceMaps loaded(testParams());
  const IoResult result = loadPlaces(path, &loaded);
  ASSERT_TRUE(result) << result.error;
  expectSamePlaces(places, loaded);
  EXPECT_EQ(encodePlaces(loaded), readFile(path));  // bit for bit
  EXPECT_FALSE(loaded.activeId().has_value());
  // The loaded maps work: a new place gets a fresh id.
  EXPECT_EQ(loaded.createPlace({}), places.nextId());
  std::remove(path.c_str());
}

class RefusedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    good_ = encodePlaces(twoPlaces());
    // The maps in memory before each load: one place of their own.
    std::mt19937 rng(9);
    kept_.createPlace({1.0, 2.0, 3.0});
    kept_.active()->update(observeAll(otherRoom(), {0, 0, 0}, kSensorMount, &rng), kSensorMount, nullptr);
    kept_bytes_ = encodePlaces(kept_);
  }
  /// Loading `bytes` from a file must fail with an error naming the file and containing `what`,
  /// and leave kept_ unchanged.
  void expectRefused(const std::string& bytes, const std::string& what) {
    const std::string path = tempPath("refused.places");
    writeFile(path, bytes);
    const IoResult result = loadPlaces(path, &kept_);
    EXPECT_FALSE(result.ok);
    EXPECT_NE(result.error.find(path), std::string::npos) << result.error;
    EXPECT_NE(result.error.find(what), std::string::npos) << result.error;
    EXPECT_EQ(encodePlaces(kept_), kept_bytes_) << "the maps in memory changed";
    EXPECT_TRUE(kept_.activeId().has_value());
    std::remove(path.c_str());
  }
  std::string good_;
  PlaceMaps kept_{testParams()};
  std::string kept_bytes_;
};

TEST_F(RefusedFile, Truncated) {
  for (const size_t keep : {size_t(0), size_t(10), size_t(30), good_.size() / 3, good_.size() / 2, good_.size() - 1,
                            good_.size() - 5}) {
    SCOPED_TRACE(keep);
    const std::string truncated = good_.substr(0, keep);
    const std::string path = tempPath("truncated.places");
    writeFile(path, truncated);
    const IoResult result = loadPlaces(path, &kept_);
    EXPECT_FALSE(result.ok);
    EXPECT_NE(result.error.find(path), std::string::npos);
    std::printf("  truncated to %zu bytes: %s\n", keep, result.error.c_str());
    EXPECT_EQ(encodePlaces(kept_), kept_bytes_);
    std::remove(path.c_str());
  }
}

TEST_F(RefusedFile, FlippedByteInANumber) {
  std::string flipped = good_;
  flipped[firstLineOffset(good_) + 3] ^= 0x10;  // inside the first line's alpha
  expectRefused(flipped, "checksum");
  std::string in_covariance = good_;
  in_covariance[good_.size() / 2] ^= 0x01;
  expectRefused(in_covariance, "checksum");
}

TEST_F(RefusedFile, BadMagic) {
  std::string bad = good_;
  bad[3] = 'X';
  expectRefused(bad, "not a places file");
  expectRefused("", "not a places file");
}

TEST_F(RefusedFile, NewerOrOlderVersion) {
  std::string newer = good_;
  const size_t at = newer.find("version 1\n");
  ASSERT_NE(at, std::string::npos);
  newer[at + 8] = '2';
  expectRefused(newer, "newer");
  std::string older = good_;
  older[at + 8] = '0';
  expectRefused(older, "format version 0 is older than this build reads (1) and has no migration");
  std::string garbage = good_;
  garbage[at + 8] = 'x';
  expectRefused(garbage, "version");
}

TEST_F(RefusedFile, NonFiniteNumberEvenWithAValidChecksum) {
  std::string nan = good_;
  const double value = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&nan[firstLineOffset(good_) + 8], &value, 8);  // the first line's r (little-endian host)
  expectRefused(withValidChecksum(nan), "non-finite");
}

TEST_F(RefusedFile, NonCanonicalLineOrIndefiniteCovariance) {
  std::string negative_r = good_;
  const double r = -1.0;
  std::memcpy(&negative_r[firstLineOffset(good_) + 8], &r, 8);
  expectRefused(withValidChecksum(negative_r), "canonical");

  // A large off-diagonal entry in place #0's covariance (last stored row: P(N-1, 0)).
  PlaceMaps places = twoPlaces();
  const Place& first = *places.place(places.placeIds()[0]);
  const size_t n = first.map.stateSize();
  std::string record;
  const size_t body = good_.find('\n', good_.find('\n') + 1) + 1;
  const size_t covariance_start = body + 8 + 4 + 24 + 4 + 4 + 4 + 24 + first.map.numLines() * 48 +
                                  first.doors.size() * (4 + 9 * 8);
  const size_t last_row = covariance_start + (n - 1) * n / 2 * 8;  // P(n-1, 0)
  std::string indefinite = good_;
  const double big = 1e3;
  std::memcpy(&indefinite[last_row], &big, 8);
  expectRefused(withValidChecksum(indefinite), "positive semi-definite");
}

TEST_F(RefusedFile, TrailingBytes) {
  std::string longer = good_;
  longer.insert(longer.size() - 4, "abcd");
  expectRefused(withValidChecksum(longer), "unexpected bytes");
}

TEST_F(RefusedFile, MissingFile) {
  const IoResult result = loadPlaces(tempPath("does_not_exist.places"), &kept_);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find("cannot open"), std::string::npos);
  EXPECT_EQ(encodePlaces(kept_), kept_bytes_);
}

TEST(Persistence, WriteIsAtomic) {
  const PlaceMaps places = twoPlaces();
  // A directory that does not exist: an error, no file.
  const std::string missing_dir = tempPath("no_such_dir") + "/places.bin";
  const IoResult failed = savePlaces(places, missing_dir);
  EXPECT_FALSE(failed.ok);
  EXPECT_NE(failed.error.find(missing_dir), std::string::npos) << failed.error;
  EXPECT_FALSE(exists(missing_dir));
  EXPECT_FALSE(exists(missing_dir + ".tmp"));

  // An existing map is not damaged by a failed save (the temporary cannot be created: it is a
  // directory), and no partial file replaces it.
  const std::string path = tempPath("atomic.places");
  ASSERT_TRUE(savePlaces(places, path));
  const std::string before = readFile(path);
  ASSERT_EQ(::mkdir((path + ".tmp").c_str(), 0755), 0);
  PlaceMaps other(testParams());
  other.createPlace({});
  EXPECT_FALSE(savePlaces(other, path).ok);
  EXPECT_EQ(readFile(path), before);
  ::rmdir((path + ".tmp").c_str());
  // Saving again works and replaces the file.
  ASSERT_TRUE(savePlaces(other, path));
  PlaceMaps loaded(testParams());
  ASSERT_TRUE(loadPlaces(path, &loaded));
  EXPECT_EQ(loaded.size(), 1u);
  std::remove(path.c_str());
}

TEST(Persistence, StorageSizePerSquareMetre) {
  const PlaceMaps places = twoPlaces();
  const std::vector<PlaceStorage> stats = storageStats(places);
  ASSERT_EQ(stats.size(), 2u);
  size_t total = 0;
  for (const PlaceStorage& s : stats) {
    std::printf("place %u: %zu lines, %zu bytes (lines with extents: %zu), %.1f m^2 -> %.1f bytes/m^2 "
                "(lines only %.1f bytes/m^2)\n",
                s.id, s.lines, s.bytes, s.line_bytes, s.area_m2, s.bytes_per_m2, s.line_bytes_per_m2);
    EXPECT_GT(s.area_m2, 10.0);
    EXPECT_GT(s.bytes, s.line_bytes);
    total += s.bytes;
  }
  // The whole file: header, counts and checksum around the place records.
  EXPECT_EQ(encodePlaces(places).size(), total + std::strlen("hybrid_slam_places\nversion 1\n") + 8 + 4);
  // The office room (7 lines, 27 m^2): the full covariance dominates; an 8-bit grid at 5 cm takes 400 bytes/m^2.
  EXPECT_LT(stats[0].bytes_per_m2, 400.0);
}

}  // namespace
}  // namespace ekf_local_map
