// Saving and loading the topological map: a round trip of every field within float32's bounds (and
// bit for bit from then on); version-1 and version-2 files still read; record sizes; refusal of a
// wrong magic line, newer/unknown versions, flipped bytes anywhere, truncation, trailing bytes, and
// of structurally invalid content behind a valid checksum (non-finite numbers, unnormalized angles,
// negative lengths/widths, p_lmap outside [0, 1], unknown types, duplicate ids, dangling edges,
// self-loops), always keeping the map in memory; atomic writes; empty maps.
#include "pomdp_topo/map_io.h"

#include "laser_features/file_io.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace pomdp_topo {
namespace {

using laser_features::kPi;

const std::string kHeader = "hybrid_slam_topological_map\nversion 4\n";

/// How two maps must agree: exactly, or within the float32 bounds of map_io.h (reals within 6e-8
/// of their size, angles within 2.4e-7 rad).
enum class Precision { kExact, kFloat32 };

::testing::AssertionResult nearReal(double a, double b, Precision precision) {
  const double bound = precision == Precision::kExact ? 0.0 : 6e-8 * std::abs(a);
  if (std::abs(a - b) <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << ": more than " << bound << " apart";
}

::testing::AssertionResult nearAngle(double a, double b, Precision precision) {
  const double bound = precision == Precision::kExact ? 0.0 : 2.4e-7;
  if (std::abs(laser_features::normalizeAngle(a - b)) <= bound) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << ": more than " << bound << " rad apart";
}

std::string tempPath(const std::string& name) {
  return ::testing::TempDir() + "pomdp_topo_" + std::to_string(::getpid()) + "_" + name;
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

/// A map with every field set to a distinct, non-default value.
TopologicalMap fullMap() {
  TopologicalMap map;
  TopoNode door;
  door.type = NodeType::Door;
  door.pose = {1.25, -3.5, kPi};  // pi itself is inside (-pi, pi]
  door.openings = {{0.5, 0.45, 0.9, true, 7, {0.3, -0.2, -2.75}}, {-1.5, 0.0, 1.1, true, 0, {-1.0, 4.0, 0.25}}};
  door.fingerprint.entries = {{FingerprintEntry::Corner, -2.5}, {FingerprintEntry::Opening, 0.1},
                              {FingerprintEntry::LineDirection, 1.5707963267948966}};
  door.explored = true;
  const uint32_t a = map.addNode(door);

  TopoNode junction;
  junction.type = NodeType::Junction;
  junction.pose = {10.0, 2.0, 0.001};
  junction.openings = {{3.0, 1.2, 1.8, true}, {-0.2, 1.0, 2.0, true}, {1.4, 0.8, 0.0, false}};
  junction.fingerprint.entries = {{FingerprintEntry::Opening, -3.1}};
  const uint32_t b = map.addNode(junction);

  TopoNode end;
  end.type = NodeType::HallwayEnd;
  end.pose = {-4.0, 8.5, -1.0};
  const uint32_t c = map.addNode(end);

  TopoNode start;
  start.type = NodeType::Start;
  const uint32_t d = map.addNode(start);
  TopoNode place;
  place.type = NodeType::Place;
  const uint32_t removed = map.addNode(place);  // its id is not reused: next ids jump

  EdgeLandmark corner{LandmarkType::Corner, 2.5, -0.75, 0.785, 0.8, 12};
  EdgeLandmark opening{LandmarkType::Opening, 6.0, 1.1, -1.57, 0.35, 3};
  EdgeLandmark far{LandmarkType::Corner, 8.9, 0.0, kPi, 1.0, 4000000000u};
  map.addEdge(a, b, 0.02, 9.1, {opening, corner, far});
  map.addEdge(b, c, 2.0, 7.25, {{LandmarkType::Opening, 0.0, -1.0, 0.0, 0.0, 0}});
  map.addEdge(d, a, -1.6, 0.0);
  const uint32_t gone = map.addEdge(c, d, 1.0, 3.0);
  map.removeEdge(gone);
  map.removeNode(removed);
  return map;
}

void expectSameMaps(const TopologicalMap& a, const TopologicalMap& b, Precision precision) {
  const Precision& m = precision;
  EXPECT_EQ(a.nextNodeId(), b.nextNodeId());
  EXPECT_EQ(a.nextEdgeId(), b.nextEdgeId());
  ASSERT_EQ(a.nodeCount(), b.nodeCount());
  ASSERT_EQ(a.edgeCount(), b.edgeCount());
  for (const auto& entry : a.nodes()) {
    const TopoNode& p = entry.second;
    const TopoNode* q = b.node(entry.first);
    ASSERT_NE(q, nullptr) << "node " << entry.first;
    EXPECT_EQ(p.id, q->id);
    EXPECT_EQ(p.type, q->type);
    EXPECT_TRUE(nearReal(p.pose.x, q->pose.x, m));
    EXPECT_TRUE(nearReal(p.pose.y, q->pose.y, m));
    EXPECT_TRUE(nearAngle(p.pose.theta, q->pose.theta, m));
    EXPECT_EQ(p.explored, q->explored);
    ASSERT_EQ(p.openings.size(), q->openings.size());
    for (size_t i = 0; i < p.openings.size(); ++i) {
      EXPECT_TRUE(nearAngle(p.openings[i].bearing, q->openings[i].bearing, m));
      EXPECT_TRUE(nearReal(p.openings[i].offset, q->openings[i].offset, m));
      EXPECT_TRUE(nearReal(p.openings[i].width, q->openings[i].width, m));
      EXPECT_EQ(p.openings[i].explored, q->openings[i].explored);
      EXPECT_EQ(p.openings[i].place_id, q->openings[i].place_id);
      EXPECT_TRUE(nearReal(p.openings[i].door_in_place.x, q->openings[i].door_in_place.x, m));
      EXPECT_TRUE(nearReal(p.openings[i].door_in_place.y, q->openings[i].door_in_place.y, m));
      EXPECT_TRUE(nearAngle(p.openings[i].door_in_place.theta, q->openings[i].door_in_place.theta, m));
      EXPECT_TRUE(nearAngle(p.openings[i].skew, q->openings[i].skew, m));
    }
    ASSERT_EQ(p.fingerprint.entries.size(), q->fingerprint.entries.size());
    for (size_t i = 0; i < p.fingerprint.entries.size(); ++i) {
      EXPECT_EQ(p.fingerprint.entries[i].kind, q->fingerprint.entries[i].kind);
      EXPECT_TRUE(nearAngle(p.fingerprint.entries[i].bearing, q->fingerprint.entries[i].bearing, m));
    }
  }
  for (const auto& entry : a.edges()) {
    const TopoEdge& e = entry.second;
    const TopoEdge* f = b.edge(entry.first);
    ASSERT_NE(f, nullptr) << "edge " << entry.first;
    EXPECT_EQ(e.id, f->id);
    EXPECT_EQ(e.source, f->source);
    EXPECT_EQ(e.target, f->target);
    EXPECT_TRUE(nearAngle(e.heading, f->heading, m));
    EXPECT_TRUE(nearReal(e.length, f->length, m));
    ASSERT_EQ(e.landmarks.size(), f->landmarks.size());
    for (size_t i = 0; i < e.landmarks.size(); ++i) {
      EXPECT_EQ(e.landmarks[i].type, f->landmarks[i].type);
      EXPECT_TRUE(nearReal(e.landmarks[i].distance, f->landmarks[i].distance, m));
      EXPECT_TRUE(nearReal(e.landmarks[i].lateral, f->landmarks[i].lateral, m));
      EXPECT_TRUE(nearAngle(e.landmarks[i].orientation, f->landmarks[i].orientation, m));
      EXPECT_TRUE(nearReal(e.landmarks[i].p_lmap, f->landmarks[i].p_lmap, m));
      EXPECT_EQ(e.landmarks[i].observations, f->landmarks[i].observations);
    }
  }
}

// ---- byte offsets in an encoded map (see the format in map_io.h) ------------------------------

size_t bodyOffset(const std::string& bytes) { return bytes.find('\n', bytes.find('\n') + 1) + 1; }

// Record sizes of version 4 (map_io.h) and field offsets inside them.
constexpr size_t kNodeBytes = 26, kOpeningBytes = 33, kEntryBytes = 5, kEdgeBytes = 24, kLandmarkBytes = 21;
constexpr size_t kNodeType = 4, kNodeX = 5, kNodeTheta = 13, kNodeFlags = 17, kNodeOpeningCount = 18;
constexpr size_t kOpeningOffset = 4, kOpeningWidth = 8, kOpeningFlags = 12, kOpeningPlace = 13, kOpeningDoorX = 17,
                 kOpeningDoorTheta = 25;
constexpr size_t kEdgeTarget = 8, kEdgeHeading = 12, kEdgeLength = 16, kEdgeLandmarkCount = 20;
constexpr size_t kLandmarkLateral = 5, kLandmarkOrientation = 9, kLandmarkPlmap = 13;

size_t nodeRecordSize(const TopoNode& node) {
  return kNodeBytes + kOpeningBytes * node.openings.size() + kEntryBytes * node.fingerprint.entries.size();
}

/// Offset of the record of the `index`-th node (in id order).
size_t nodeOffset(const TopologicalMap& map, const std::string& bytes, size_t index) {
  size_t at = bodyOffset(bytes) + 4;
  auto it = map.nodes().begin();
  for (size_t i = 0; i < index; ++i, ++it) at += nodeRecordSize(it->second);
  return at;
}

/// Offset of the record of the `index`-th edge (in id order).
size_t edgeOffset(const TopologicalMap& map, const std::string& bytes, size_t index) {
  size_t at = nodeOffset(map, bytes, map.nodeCount()) + 4;
  auto it = map.edges().begin();
  for (size_t i = 0; i < index; ++i, ++it) at += kEdgeBytes + kLandmarkBytes * it->second.landmarks.size();
  return at;
}

void putU32(std::string* bytes, size_t at, uint32_t v) {
  for (int b = 0; b < 4; ++b) (*bytes)[at + size_t(b)] = char((v >> (8 * b)) & 0xffu);
}
void putF64(std::string* bytes, size_t at, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  for (int b = 0; b < 8; ++b) (*bytes)[at + size_t(b)] = char((bits >> (8 * b)) & 0xffu);
}
void putF32(std::string* bytes, size_t at, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  putU32(bytes, at, bits);
}

/// Replaces the trailing CRC so that a deliberately altered body passes the checksum.
std::string withValidChecksum(std::string bytes) {
  putU32(&bytes, bytes.size() - 4, laser_features::crc32(bytes.data(), bytes.size() - 4));
  return bytes;
}

TEST(MapIo, RoundTripOfEveryFieldWithinFloat32) {
  const TopologicalMap map = fullMap();
  ASSERT_EQ(map.nodeCount(), 4u);
  ASSERT_EQ(map.edgeCount(), 3u);
  const std::string path = tempPath("round_trip.topo");
  const IoResult saved = saveMap(map, path);
  ASSERT_TRUE(saved) << saved.error;
  EXPECT_FALSE(exists(path + ".tmp"));
  const std::string bytes = readFile(path);
  EXPECT_EQ(bytes.rfind(kHeader, 0), 0u);
  EXPECT_EQ(bytes, encodeMap(map));

  TopologicalMap loaded;
  loaded.addNode({});
  const uint64_t revision = loaded.revision();
  const IoResult result = loadMap(path, &loaded);
  ASSERT_TRUE(result) << result.error;
  expectSameMaps(map, loaded, Precision::kFloat32);
  EXPECT_NE(loaded.edge(0)->landmarks[1].orientation, map.edge(0)->landmarks[1].orientation);  // 0.785 is no float
  EXPECT_GT(loaded.revision(), revision);  // the localizer sees the change
  EXPECT_EQ(encodeMap(loaded), bytes);     // bit for bit from then on
  // The loaded map works: new ids continue after the stored next ids.
  EXPECT_EQ(loaded.addNode({}), map.nextNodeId());
  EXPECT_EQ(loaded.addEdge(0, 1, 0.0, 1.0), map.nextEdgeId());
  std::remove(path.c_str());
}

TEST(MapIo, EmptyMapRoundTrips) {
  TopologicalMap empty;
  TopologicalMap loaded = fullMap();
  ASSERT_TRUE(decodeMap(encodeMap(empty), "empty", &loaded));
  EXPECT_TRUE(loaded.empty());
  EXPECT_EQ(loaded.edgeCount(), 0u);
  EXPECT_EQ(loaded.nextNodeId(), 0u);
  EXPECT_EQ(loaded.nextEdgeId(), 0u);
  EXPECT_EQ(encodeMap(empty).size(), kHeader.size() + 4 * 5);

  // Empty, but with ids already used: through a file.
  TopologicalMap emptied;
  emptied.removeNode(emptied.addNode({}));
  const std::string path = tempPath("empty.topo");
  ASSERT_TRUE(saveMap(emptied, path));
  ASSERT_TRUE(loadMap(path, &loaded));
  EXPECT_TRUE(loaded.empty());
  EXPECT_EQ(loaded.nextNodeId(), 1u);
  std::remove(path.c_str());
}

TEST(MapIo, AnglesAreNormalizedWhenWritten) {
  TopologicalMap map;
  TopoNode node;
  node.pose.theta = -kPi;  // the same direction as pi
  node.openings = {{2 * kPi + 0.5, 1.0, 1.0, false}};
  map.addNode(node);
  TopologicalMap loaded;
  const IoResult result = decodeMap(encodeMap(map), "angles", &loaded);
  ASSERT_TRUE(result) << result.error;
  EXPECT_LE(loaded.node(0)->pose.theta, kPi);  // pi rounded to float32 stays inside (-pi, pi]
  EXPECT_NEAR(loaded.node(0)->pose.theta, kPi, 2.4e-7);
  EXPECT_NEAR(loaded.node(0)->openings[0].bearing, 0.5, 3e-8);
}

/// A version-1 file (one place per node, stored with the node) of one door node with two openings
/// linking place `place` (-1: none), or with no opening.
std::string versionOneFile(int32_t place, bool openings = true) {
  std::string b = "hybrid_slam_topological_map\nversion 1\n";
  auto u32 = [&b](uint32_t v) {
    for (int k = 0; k < 4; ++k) b.push_back(char((v >> (8 * k)) & 0xffu));
  };
  auto f64 = [&b](double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    for (int k = 0; k < 8; ++k) b.push_back(char((bits >> (8 * k)) & 0xffu));
  };
  u32(1);                                   // node count
  u32(3), u32(uint32_t(NodeType::Door));    // id, type
  f64(1.0), f64(2.0), f64(0.5);             // pose
  u32(uint32_t(place));                     // the node's place
  f64(0.25), f64(-0.5), f64(1.5);           // its door in the place
  u32(1);                                   // flags: explored
  u32(openings ? 2 : 0), u32(0);            // openings, fingerprint entries
  if (openings) {
    f64(-1.5), f64(0.4), f64(0.9), u32(1);  // the door entered first (linking put it first)
    f64(1.6), f64(0.4), f64(1.0), u32(0);   // the door across
  }
  u32(0);                                   // edge count
  u32(4), u32(0);                           // next ids
  u32(0);                                   // checksum, set below
  return withValidChecksum(b);
}

TEST(MapIo, AVersionOneFileIsReadWithItsNodesPlaceOnTheFirstOpening) {
  TopologicalMap loaded;
  const IoResult result = decodeMap(versionOneFile(12), "v1", &loaded);
  ASSERT_TRUE(result) << result.error;
  const TopoNode* n = loaded.node(3);
  ASSERT_NE(n, nullptr);
  ASSERT_EQ(n->openings.size(), 2u);
  EXPECT_EQ(n->openings[0].place_id, 12);
  EXPECT_EQ(n->openings[0].door_in_place.x, 0.25);
  EXPECT_EQ(n->openings[0].door_in_place.theta, 1.5);
  EXPECT_EQ(n->openings[1].place_id, -1);
  EXPECT_TRUE(n->explored);
  EXPECT_EQ(loaded.nextNodeId(), 4u);
  // Saved again, it is version 4, and reads back within float32.
  const std::string again = encodeMap(loaded);
  EXPECT_EQ(again.rfind(kHeader, 0), 0u);
  TopologicalMap reloaded;
  ASSERT_TRUE(decodeMap(again, "v4", &reloaded));
  expectSameMaps(loaded, reloaded, Precision::kFloat32);
  // Without a place: no opening links one.
  ASSERT_TRUE(decodeMap(versionOneFile(-1), "v1", &loaded));
  EXPECT_EQ(loaded.node(3)->openings[0].place_id, -1);
  // A place but no door to put it on, or a place id below -1: refused.
  TopologicalMap kept;
  const IoResult no_door = decodeMap(versionOneFile(5, false), "v1", &kept);
  EXPECT_FALSE(no_door.ok);
  EXPECT_NE(no_door.error.find("links place 5 but has no opening"), std::string::npos) << no_door.error;
  const IoResult negative = decodeMap(versionOneFile(-3), "v1", &kept);
  EXPECT_FALSE(negative.ok);
  EXPECT_NE(negative.error.find("place id -3"), std::string::npos) << negative.error;
  EXPECT_TRUE(kept.empty());
}

TEST(MapIo, AVersionTwoFileIsStillRead) {
  // Written by the version-2 code (at 359597d) from fullMap(): f64 numbers, u32 codes.
  const std::string path = std::string(TEST_DATA_DIR) + "/full_map_v2.topo";
  const std::string bytes = readFile(path);
  ASSERT_EQ(bytes.rfind("hybrid_slam_topological_map\nversion 2\n", 0), 0u) << path;
  TopologicalMap loaded;
  const IoResult result = loadMap(path, &loaded);
  ASSERT_TRUE(result) << result.error;
  expectSameMaps(fullMap(), loaded, Precision::kExact);
  // Saved again, it is version 4, smaller (f32 for f64, u8 for u32), and within float32 of it.
  const std::string again = encodeMap(loaded);
  EXPECT_EQ(again.rfind(kHeader, 0), 0u);
  EXPECT_LT(again.size(), bytes.size() * 2 / 3);
  TopologicalMap reloaded;
  ASSERT_TRUE(decodeMap(again, "v4", &reloaded));
  expectSameMaps(loaded, reloaded, Precision::kFloat32);

  // Version 2's wide fields are checked as before (node #0's pose x, theta and type, in f64 / u32).
  const size_t node0 = bytes.find('\n', bytes.find('\n') + 1) + 1 + 4;
  TopologicalMap kept;
  std::string nan = bytes;
  putF64(&nan, node0 + 8, std::numeric_limits<double>::quiet_NaN());
  const IoResult non_finite = decodeMap(withValidChecksum(nan), "v2", &kept);
  EXPECT_NE(non_finite.error.find("non-finite number in a node pose at byte " + std::to_string(node0 + 8)),
            std::string::npos) << non_finite.error;
  std::string angle = bytes;
  putF64(&angle, node0 + 24, 3.5);
  const IoResult outside = decodeMap(withValidChecksum(angle), "v2", &kept);
  EXPECT_NE(outside.error.find("at byte " + std::to_string(node0 + 24) + " is not in (-pi, pi]"), std::string::npos)
      << outside.error;
  std::string type = bytes;
  putU32(&type, node0 + 4, 0x100u);  // a u32 code: 256, not 0
  const IoResult unknown = decodeMap(withValidChecksum(type), "v2", &kept);
  EXPECT_NE(unknown.error.find("unknown node type 256"), std::string::npos) << unknown.error;
  EXPECT_TRUE(kept.empty());
}

TEST(MapIo, AVersionThreeFileIsReadWithEveryOpeningOnTheAxes) {
  // Written by the version-3 code (at d9029b0) from fullMap(): no skew, so every opening's
  // direction is its bearing.
  const std::string path = std::string(TEST_DATA_DIR) + "/full_map_v3.topo";
  const std::string v3 = readFile(path);
  ASSERT_EQ(v3.rfind("hybrid_slam_topological_map\nversion 3\n", 0), 0u) << path;
  TopologicalMap loaded;
  const IoResult result = loadMap(path, &loaded);
  ASSERT_TRUE(result) << result.error;
  expectSameMaps(fullMap(), loaded, Precision::kFloat32);
  size_t openings = 0;
  for (const auto& [id, node] : loaded.nodes()) {
    for (const NodeOpening& o : node.openings) EXPECT_EQ(o.direction(), o.bearing) << "node " << id;
    openings += node.openings.size();
  }
  // Saved again, it is version 4: version 3's bytes and a skew (f32) per opening.
  const std::string again = encodeMap(loaded);
  EXPECT_EQ(again.rfind(kHeader, 0), 0u);
  EXPECT_EQ(again.size(), v3.size() + 4 * openings);
}

TEST(MapIo, AWingsDoorKeepsItsSkewAndSoItsDirection) {
  // A door seen from a wing 40 deg off its bin: stored across the bin, facing across the wing.
  TopologicalMap map = fullMap();
  TopoNode* door = map.node(map.nodes().begin()->first);
  ASSERT_FALSE(door->openings.empty());
  door->openings[0].skew = -0.7;
  TopologicalMap loaded;
  ASSERT_TRUE(decodeMap(encodeMap(map), "wing", &loaded));
  expectSameMaps(map, loaded, Precision::kFloat32);
  const NodeOpening& o = loaded.node(door->id)->openings[0];
  EXPECT_NEAR(o.direction(), laser_features::normalizeAngle(door->openings[0].bearing - 0.7), 1e-6);
  // A skew outside (-pi, pi] in the file is refused like any angle.
  std::string bad = encodeMap(map);
  const size_t skew_at = bodyOffset(bad) + 4 + kNodeBytes + kOpeningBytes - 4;
  putF32(&bad, skew_at, 4.0f);
  TopologicalMap kept;
  const IoResult refused = decodeMap(withValidChecksum(bad), "wing", &kept);
  EXPECT_NE(refused.error.find("not in (-pi, pi]"), std::string::npos) << refused.error;
}

TEST(MapIo, RecordSizes) {
  // As map_io.h states: a node 26 bytes + 33 an opening + 5 a fingerprint entry, an edge 24 bytes
  // + 21 a landmark; around them the header, the counts, the next ids and the CRC.
  const TopologicalMap map = fullMap();
  size_t records = 0, openings = 0, entries = 0, landmarks = 0;
  for (const auto& [id, node] : map.nodes()) {
    records += 26 + 33 * node.openings.size() + 5 * node.fingerprint.entries.size();
    openings += node.openings.size();
    entries += node.fingerprint.entries.size();
  }
  for (const auto& [id, edge] : map.edges()) {
    records += 24 + 21 * edge.landmarks.size();
    landmarks += edge.landmarks.size();
  }
  EXPECT_EQ(encodeMap(map).size(), kHeader.size() + 4 + 4 + records + 8 + 4);
  EXPECT_GT(openings * entries * landmarks, 0u);
  const std::string v2 = readFile(std::string(TEST_DATA_DIR) + "/full_map_v2.topo");
  std::printf("  fullMap(): %zu nodes, %zu openings, %zu fingerprint entries, %zu edges, %zu landmarks: "
              "%zu bytes (version 2: %zu)\n",
              map.nodeCount(), openings, entries, map.edgeCount(), landmarks, encodeMap(map).size(), v2.size());
}

class RefusedFile : public ::testing::Test {
 protected:
  void SetUp() override {
    map_ = fullMap();
    good_ = encodeMap(map_);
    // The map in memory before each load: different content of its own.
    const uint32_t a = kept_.addNode({});
    const uint32_t b = kept_.addNode({});
    kept_.addEdge(a, b, 1.0, 4.0);
    kept_bytes_ = encodeMap(kept_);
    kept_revision_ = kept_.revision();
  }
  /// Loading `bytes` from a file must fail with an error naming the file and containing `what`,
  /// and leave kept_ unchanged.
  void expectRefused(const std::string& bytes, const std::string& what) {
    const std::string path = tempPath("refused.topo");
    writeFile(path, bytes);
    const IoResult result = loadMap(path, &kept_);
    EXPECT_FALSE(result.ok);
    EXPECT_FALSE(bool(result));
    EXPECT_NE(result.error.find(path), std::string::npos) << result.error;
    EXPECT_NE(result.error.find(what), std::string::npos) << result.error;
    std::printf("  %s\n", result.error.c_str() + result.error.find("': ") + 3);
    expectKept();
    std::remove(path.c_str());
  }
  void expectKept() {
    EXPECT_TRUE(encodeMap(kept_) == kept_bytes_) << "the map in memory changed";
    EXPECT_EQ(kept_.revision(), kept_revision_);
  }
  /// `good_` with the f32 at `at` replaced, checksum recomputed.
  std::string patchF32(size_t at, float v) const {
    std::string bytes = good_;
    putF32(&bytes, at, v);
    return withValidChecksum(bytes);
  }
  std::string patchU8(size_t at, uint8_t v) const {
    std::string bytes = good_;
    bytes[at] = char(v);
    return withValidChecksum(bytes);
  }
  std::string patchU32(size_t at, uint32_t v) const {
    std::string bytes = good_;
    putU32(&bytes, at, v);
    return withValidChecksum(bytes);
  }
  size_t node(size_t index) const { return nodeOffset(map_, good_, index); }
  size_t edge(size_t index) const { return edgeOffset(map_, good_, index); }

  TopologicalMap map_;
  std::string good_;
  TopologicalMap kept_;
  std::string kept_bytes_;
  uint64_t kept_revision_ = 0;
};

TEST_F(RefusedFile, OffsetsOfThisTestMatchTheFormat) {
  // Sanity of the helpers the other tests patch with: the body ends with the next ids and the CRC.
  EXPECT_EQ(edgeOffset(map_, good_, map_.edgeCount()) + 8 + 4, good_.size());
}

TEST_F(RefusedFile, WrongMagic) {
  std::string bad = good_;
  bad[3] = 'X';
  expectRefused(bad, "not a topological map file");
  expectRefused("", "not a topological map file");
  expectRefused("hybrid_slam_places\nversion 1\n", "not a topological map file");
}

TEST_F(RefusedFile, NewerOrUnknownVersion) {
  const size_t at = good_.find("version 4\n");
  ASSERT_NE(at, std::string::npos);
  std::string newer = good_;
  newer[at + 8] = '5';
  expectRefused(newer, "format version 5 is newer than this build reads (4); update the software");
  std::string older = good_;
  older[at + 8] = '0';
  expectRefused(older, "format version 0 is older than this build reads (1..4) and has no migration");
  std::string garbage = good_;
  garbage[at + 8] = 'x';
  expectRefused(garbage, "malformed version line");
  expectRefused("hybrid_slam_topological_map\nversion 1", "malformed version line");
}

TEST_F(RefusedFile, AFlippedByteAnywhereFails) {
  for (size_t at = 0; at < good_.size(); ++at) {
    for (const int bit : {0x01, 0x80}) {
      std::string flipped = good_;
      flipped[at] = char(flipped[at] ^ bit);
      const IoResult result = decodeMap(flipped, "flipped", &kept_);
      ASSERT_FALSE(result.ok) << "byte " << at << " bit " << bit;
      if (at >= bodyOffset(good_)) {
        EXPECT_NE(result.error.find("checksum"), std::string::npos) << result.error;
      }
    }
  }
  expectKept();
  std::string flipped = good_;
  flipped[node(0) + 10] ^= 0x10;  // inside the first node's pose
  expectRefused(flipped, "checksum mismatch");
}

TEST_F(RefusedFile, Truncated) {
  for (size_t keep = 0; keep < good_.size(); ++keep) {
    const IoResult result = decodeMap(good_.substr(0, keep), "truncated", &kept_);
    ASSERT_FALSE(result.ok) << keep;
  }
  expectKept();
  expectRefused(good_.substr(0, good_.size() / 2), "truncated");
  expectRefused(good_.substr(0, bodyOffset(good_) + 2), "ends early");
  // A truncated file whose checksum happens to match: the structure still says it ends early.
  std::string cut = good_.substr(0, edge(1));
  cut.resize(cut.size() + 4);
  expectRefused(withValidChecksum(cut), "ends early");
}

TEST_F(RefusedFile, ImpossibleCountsAreRefusedBeforeAllocating) {
  expectRefused(patchU32(bodyOffset(good_), 0xffffffffu), "truncated?");
  expectRefused(patchU32(node(0) + kNodeOpeningCount, 0x7fffffffu), "openings");
  expectRefused(patchU32(edge(0) + kEdgeLandmarkCount, 0xffffffffu), "landmarks");
}

TEST_F(RefusedFile, TrailingBytes) {
  std::string longer = good_;
  longer.insert(longer.size() - 4, "abcd");
  expectRefused(withValidChecksum(longer), "unexpected bytes");
  expectRefused(good_ + "x", "checksum");  // after the checksum
}

TEST_F(RefusedFile, NonFiniteNumbers) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  expectRefused(patchF32(node(0) + kNodeX, nan), "non-finite number in a node pose at byte " +
                                                     std::to_string(node(0) + kNodeX));
  expectRefused(patchF32(node(1) + kNodeBytes + kOpeningOffset, inf), "non-finite");
  expectRefused(patchF32(node(0) + kNodeBytes + kOpeningDoorX, nan), "non-finite");
  expectRefused(patchF32(edge(0) + kEdgeBytes + kLandmarkLateral, -inf), "non-finite");
}

TEST_F(RefusedFile, AnglesOutsideMinusPiPi) {
  expectRefused(patchF32(node(0) + kNodeTheta, 3.5f), "at byte " + std::to_string(node(0) + kNodeTheta) +
                                                         " is not in (-pi, pi]");
  expectRefused(patchF32(node(0) + kNodeTheta, float(kPi)), "not in (-pi, pi]");  // float(pi) > pi
  expectRefused(patchF32(node(0) + kNodeTheta, -float(kPi)), "not in (-pi, pi]");
  expectRefused(patchF32(node(0) + kNodeBytes + kOpeningDoorTheta, 7.0f), "not in (-pi, pi]");
  expectRefused(patchF32(node(0) + kNodeBytes, -4.0f), "not in (-pi, pi]");  // opening bearing
  expectRefused(patchF32(node(0) + kNodeBytes + 2 * kOpeningBytes + 1, 4.0f), "not in (-pi, pi]");  // fingerprint
  expectRefused(patchF32(edge(0) + kEdgeHeading, 3.2f), "not in (-pi, pi]");
  expectRefused(patchF32(edge(0) + kEdgeBytes + kLandmarkOrientation, -3.2f), "not in (-pi, pi]");
}

TEST_F(RefusedFile, NegativeLengthsAndWidths) {
  expectRefused(patchF32(edge(1) + kEdgeLength, -0.5f), "negative length");
  expectRefused(patchF32(node(0) + kNodeBytes + kOpeningWidth, -0.1f), "negative width");
}

TEST_F(RefusedFile, ProbabilityOutsideZeroOne) {
  expectRefused(patchF32(edge(0) + kEdgeBytes + kLandmarkPlmap, 1.5f), "p_lmap");
  expectRefused(patchF32(edge(0) + kEdgeBytes + kLandmarkBytes + kLandmarkPlmap, -0.01f), "p_lmap");
}

TEST_F(RefusedFile, UnknownTypesKindsAndFlags) {
  expectRefused(patchU8(node(1) + kNodeType, 5), "unknown node type 5");
  expectRefused(patchU8(edge(0) + kEdgeBytes, 2), "unknown landmark type 2");
  expectRefused(patchU8(node(0) + kNodeBytes + 2 * kOpeningBytes, 3), "unknown kind 3");
  expectRefused(patchU8(node(0) + kNodeFlags, 2), "unknown flags");
  expectRefused(patchU8(node(0) + kNodeBytes + kOpeningFlags, 7), "unknown flags");
  expectRefused(patchU32(node(0) + kNodeBytes + kOpeningPlace, uint32_t(-2)), "place id -2");
}

TEST_F(RefusedFile, DuplicateIds) {
  const uint32_t first_node = map_.nodes().begin()->first;
  expectRefused(patchU32(node(1), first_node), "node id " + std::to_string(first_node) + " appears twice");
  const uint32_t first_edge = map_.edges().begin()->first;
  expectRefused(patchU32(edge(2), first_edge), "edge id " + std::to_string(first_edge) + " appears twice");
}

TEST_F(RefusedFile, EdgeToAMissingNodeOrASelfLoop) {
  expectRefused(patchU32(edge(0) + kEdgeTarget, 999), "missing node 999");
  expectRefused(patchU32(edge(1) + 4, 4), "missing node 4");  // the removed node's id
  const uint32_t source = map_.edges().begin()->second.source;
  expectRefused(patchU32(edge(0) + kEdgeTarget, source), "self-loop");
}

TEST_F(RefusedFile, NextIdsBelowUsedIds) {
  const size_t next_ids = edge(map_.edgeCount());
  expectRefused(patchU32(next_ids, 3), "next node id 3");
  expectRefused(patchU32(next_ids + 4, 0), "next edge id 0");
}

TEST_F(RefusedFile, MissingFile) {
  const std::string path = tempPath("does_not_exist.topo");
  const IoResult result = loadMap(path, &kept_);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find(path), std::string::npos);
  EXPECT_NE(result.error.find("cannot open"), std::string::npos);
  expectKept();
}

TEST_F(RefusedFile, FailedLoadKeepsTheMapAndAGoodLoadReplacesIt) {
  const std::string path = tempPath("replace.topo");
  writeFile(path, good_.substr(0, good_.size() - 1));
  EXPECT_FALSE(loadMap(path, &kept_).ok);
  expectKept();
  writeFile(path, good_);
  ASSERT_TRUE(loadMap(path, &kept_));
  expectSameMaps(map_, kept_, Precision::kFloat32);
  std::remove(path.c_str());
}

TEST(MapIo, SaveIsAtomic) {
  const TopologicalMap map = fullMap();
  // A directory that does not exist: an error naming the file, no file, no .tmp.
  const std::string missing = tempPath("no_such_dir") + "/map.topo";
  const IoResult failed = saveMap(map, missing);
  EXPECT_FALSE(failed.ok);
  EXPECT_NE(failed.error.find(missing), std::string::npos) << failed.error;
  std::printf("  %s\n", failed.error.c_str());
  EXPECT_FALSE(exists(missing));
  EXPECT_FALSE(exists(missing + ".tmp"));

  // A failed save does not damage an existing file (the temporary cannot be created).
  const std::string path = tempPath("atomic.topo");
  ASSERT_TRUE(saveMap(map, path));
  const std::string before = readFile(path);
  ASSERT_EQ(::mkdir((path + ".tmp").c_str(), 0755), 0);
  TopologicalMap other;
  other.addNode({});
  EXPECT_FALSE(saveMap(other, path).ok);
  EXPECT_EQ(readFile(path), before);
  ::rmdir((path + ".tmp").c_str());
  ASSERT_TRUE(saveMap(other, path));
  TopologicalMap loaded;
  ASSERT_TRUE(loadMap(path, &loaded));
  EXPECT_EQ(loaded.nodeCount(), 1u);
  std::remove(path.c_str());
}

TEST(MapIo, AnInvalidMapIsNotSaved) {
  TopologicalMap map = fullMap();
  map.node(0)->openings[0].width = std::numeric_limits<double>::quiet_NaN();
  const std::string path = tempPath("invalid.topo");
  const IoResult result = saveMap(map, path);
  EXPECT_FALSE(result.ok);
  EXPECT_NE(result.error.find("the map is invalid"), std::string::npos) << result.error;
  EXPECT_NE(result.error.find("non-finite"), std::string::npos) << result.error;
  std::printf("  %s\n", result.error.c_str());
  EXPECT_FALSE(exists(path));
  EXPECT_FALSE(exists(path + ".tmp"));
  map.node(0)->openings[0].width = 1.0;
  map.edge(0)->landmarks[0].p_lmap = 2.0;
  EXPECT_FALSE(saveMap(map, path).ok);
  EXPECT_FALSE(exists(path));
  // A number beyond float32's range (3.4e38) would be written as infinity: refused too.
  map.edge(0)->landmarks[0].p_lmap = 0.5;
  map.edge(0)->length = 1e39;
  const IoResult too_long = saveMap(map, path);
  EXPECT_NE(too_long.error.find("non-finite"), std::string::npos) << too_long.error;
  EXPECT_FALSE(exists(path));
}

}  // namespace
}  // namespace pomdp_topo
