// Saving and loading the topological map: an exact round trip of every field; refusal of a wrong
// magic line, newer/unknown versions, flipped bytes anywhere, truncation, trailing bytes, and of
// structurally invalid content behind a valid checksum (non-finite numbers, unnormalized angles,
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

void expectSameMaps(const TopologicalMap& a, const TopologicalMap& b) {
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
    EXPECT_EQ(p.pose.x, q->pose.x);
    EXPECT_EQ(p.pose.y, q->pose.y);
    EXPECT_EQ(p.pose.theta, q->pose.theta);
    EXPECT_EQ(p.explored, q->explored);
    ASSERT_EQ(p.openings.size(), q->openings.size());
    for (size_t i = 0; i < p.openings.size(); ++i) {
      EXPECT_EQ(p.openings[i].bearing, q->openings[i].bearing);
      EXPECT_EQ(p.openings[i].offset, q->openings[i].offset);
      EXPECT_EQ(p.openings[i].width, q->openings[i].width);
      EXPECT_EQ(p.openings[i].explored, q->openings[i].explored);
      EXPECT_EQ(p.openings[i].place_id, q->openings[i].place_id);
      EXPECT_EQ(p.openings[i].door_in_place.x, q->openings[i].door_in_place.x);
      EXPECT_EQ(p.openings[i].door_in_place.y, q->openings[i].door_in_place.y);
      EXPECT_EQ(p.openings[i].door_in_place.theta, q->openings[i].door_in_place.theta);
    }
    ASSERT_EQ(p.fingerprint.entries.size(), q->fingerprint.entries.size());
    for (size_t i = 0; i < p.fingerprint.entries.size(); ++i) {
      EXPECT_EQ(p.fingerprint.entries[i].kind, q->fingerprint.entries[i].kind);
      EXPECT_EQ(p.fingerprint.entries[i].bearing, q->fingerprint.entries[i].bearing);
    }
  }
  for (const auto& entry : a.edges()) {
    const TopoEdge& e = entry.second;
    const TopoEdge* f = b.edge(entry.first);
    ASSERT_NE(f, nullptr) << "edge " << entry.first;
    EXPECT_EQ(e.id, f->id);
    EXPECT_EQ(e.source, f->source);
    EXPECT_EQ(e.target, f->target);
    EXPECT_EQ(e.heading, f->heading);
    EXPECT_EQ(e.length, f->length);
    ASSERT_EQ(e.landmarks.size(), f->landmarks.size());
    for (size_t i = 0; i < e.landmarks.size(); ++i) {
      EXPECT_EQ(e.landmarks[i].type, f->landmarks[i].type);
      EXPECT_EQ(e.landmarks[i].distance, f->landmarks[i].distance);
      EXPECT_EQ(e.landmarks[i].lateral, f->landmarks[i].lateral);
      EXPECT_EQ(e.landmarks[i].orientation, f->landmarks[i].orientation);
      EXPECT_EQ(e.landmarks[i].p_lmap, f->landmarks[i].p_lmap);
      EXPECT_EQ(e.landmarks[i].observations, f->landmarks[i].observations);
    }
  }
}

// ---- byte offsets in an encoded map (see the format in map_io.h) ------------------------------

size_t bodyOffset(const std::string& bytes) { return bytes.find('\n', bytes.find('\n') + 1) + 1; }

size_t nodeRecordSize(const TopoNode& node) {
  return 44 + 56 * node.openings.size() + 12 * node.fingerprint.entries.size();
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
  for (size_t i = 0; i < index; ++i, ++it) at += 32 + 40 * it->second.landmarks.size();
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

/// Replaces the trailing CRC so that a deliberately altered body passes the checksum.
std::string withValidChecksum(std::string bytes) {
  putU32(&bytes, bytes.size() - 4, laser_features::crc32(bytes.data(), bytes.size() - 4));
  return bytes;
}

TEST(MapIo, RoundTripOfEveryFieldIsExact) {
  const TopologicalMap map = fullMap();
  ASSERT_EQ(map.nodeCount(), 4u);
  ASSERT_EQ(map.edgeCount(), 3u);
  const std::string path = tempPath("round_trip.topo");
  const IoResult saved = saveMap(map, path);
  ASSERT_TRUE(saved) << saved.error;
  EXPECT_FALSE(exists(path + ".tmp"));
  const std::string bytes = readFile(path);
  EXPECT_EQ(bytes.rfind("hybrid_slam_topological_map\nversion 2\n", 0), 0u);
  EXPECT_EQ(bytes, encodeMap(map));

  TopologicalMap loaded;
  loaded.addNode({});
  const uint64_t revision = loaded.revision();
  const IoResult result = loadMap(path, &loaded);
  ASSERT_TRUE(result) << result.error;
  expectSameMaps(map, loaded);
  EXPECT_GT(loaded.revision(), revision);  // the localizer sees the change
  EXPECT_EQ(encodeMap(loaded), bytes);     // bit for bit
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
  EXPECT_EQ(encodeMap(empty).size(), std::strlen("hybrid_slam_topological_map\nversion 2\n") + 4 * 5);

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
  EXPECT_EQ(loaded.node(0)->pose.theta, kPi);
  EXPECT_NEAR(loaded.node(0)->openings[0].bearing, 0.5, 1e-12);
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
  // Saved again, it is version 2, and reads back the same.
  const std::string again = encodeMap(loaded);
  EXPECT_EQ(again.rfind("hybrid_slam_topological_map\nversion 2\n", 0), 0u);
  TopologicalMap reloaded;
  ASSERT_TRUE(decodeMap(again, "v2", &reloaded));
  expectSameMaps(loaded, reloaded);
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
  /// `good_` with the f64 at `at` replaced, checksum recomputed.
  std::string patchF64(size_t at, double v) const {
    std::string bytes = good_;
    putF64(&bytes, at, v);
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
  const size_t at = good_.find("version 2\n");
  ASSERT_NE(at, std::string::npos);
  std::string newer = good_;
  newer[at + 8] = '3';
  expectRefused(newer, "format version 3 is newer than this build reads (2); update the software");
  std::string older = good_;
  older[at + 8] = '0';
  expectRefused(older, "format version 0 is older than this build reads (1..2) and has no migration");
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
  expectRefused(patchU32(node(0) + 36, 0x7fffffffu), "openings");  // opening count
  expectRefused(patchU32(edge(0) + 28, 0xffffffffu), "landmarks");   // landmark count
}

TEST_F(RefusedFile, TrailingBytes) {
  std::string longer = good_;
  longer.insert(longer.size() - 4, "abcd");
  expectRefused(withValidChecksum(longer), "unexpected bytes");
  expectRefused(good_ + "x", "checksum");  // after the checksum
}

TEST_F(RefusedFile, NonFiniteNumbers) {
  expectRefused(patchF64(node(0) + 8, std::numeric_limits<double>::quiet_NaN()), "non-finite");   // pose x
  expectRefused(patchF64(node(1) + 44 + 8, std::numeric_limits<double>::infinity()), "non-finite");  // offset
  expectRefused(patchF64(node(0) + 44 + 32, std::numeric_limits<double>::quiet_NaN()), "non-finite");  // door x
  expectRefused(patchF64(edge(0) + 32 + 12, -std::numeric_limits<double>::infinity()), "non-finite");  // lateral
}

TEST_F(RefusedFile, AnglesOutsideMinusPiPi) {
  expectRefused(patchF64(node(0) + 24, 3.5), "not in (-pi, pi]");        // pose theta
  expectRefused(patchF64(node(0) + 24, -kPi), "not in (-pi, pi]");       // -pi is excluded
  expectRefused(patchF64(node(0) + 44 + 48, 7.0), "not in (-pi, pi]");   // door_in_place theta
  expectRefused(patchF64(node(0) + 44, -4.0), "not in (-pi, pi]");       // opening bearing
  expectRefused(patchF64(node(0) + 44 + 2 * 56 + 4, 4.0), "not in (-pi, pi]");  // fingerprint bearing
  expectRefused(patchF64(edge(0) + 12, 3.2), "not in (-pi, pi]");        // edge heading
  expectRefused(patchF64(edge(0) + 32 + 20, -3.2), "not in (-pi, pi]");  // landmark orientation
}

TEST_F(RefusedFile, NegativeLengthsAndWidths) {
  expectRefused(patchF64(edge(1) + 20, -0.5), "negative length");
  expectRefused(patchF64(node(0) + 44 + 16, -0.1), "negative width");
}

TEST_F(RefusedFile, ProbabilityOutsideZeroOne) {
  expectRefused(patchF64(edge(0) + 32 + 28, 1.5), "p_lmap");
  expectRefused(patchF64(edge(0) + 32 + 40 + 28, -0.01), "p_lmap");
}

TEST_F(RefusedFile, UnknownTypesKindsAndFlags) {
  expectRefused(patchU32(node(1) + 4, 5), "unknown node type 5");
  expectRefused(patchU32(edge(0) + 32, 2), "unknown landmark type 2");
  expectRefused(patchU32(node(0) + 44 + 2 * 56, 3), "unknown kind 3");
  expectRefused(patchU32(node(0) + 32, 2), "unknown flags");
  expectRefused(patchU32(node(0) + 44 + 24, 7), "unknown flags");
  expectRefused(patchU32(node(0) + 44 + 28, uint32_t(-2)), "place id -2");
}

TEST_F(RefusedFile, DuplicateIds) {
  const uint32_t first_node = map_.nodes().begin()->first;
  expectRefused(patchU32(node(1), first_node), "node id " + std::to_string(first_node) + " appears twice");
  const uint32_t first_edge = map_.edges().begin()->first;
  expectRefused(patchU32(edge(2), first_edge), "edge id " + std::to_string(first_edge) + " appears twice");
}

TEST_F(RefusedFile, EdgeToAMissingNodeOrASelfLoop) {
  expectRefused(patchU32(edge(0) + 8, 999), "missing node 999");
  expectRefused(patchU32(edge(1) + 4, 4), "missing node 4");  // the removed node's id
  const uint32_t source = map_.edges().begin()->second.source;
  expectRefused(patchU32(edge(0) + 8, source), "self-loop");
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
  expectSameMaps(map_, kept_);
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
}

}  // namespace
}  // namespace pomdp_topo
