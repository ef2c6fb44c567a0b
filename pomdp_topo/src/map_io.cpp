#include "pomdp_topo/map_io.h"

#include "laser_features/file_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>

namespace pomdp_topo {

namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;

/// The widths of a version's fields: real numbers (f64 until version 2, f32 from version 3) and
/// small codes (types, flags, kinds: u32, then u8). Ids, counts, place ids and observation counts
/// are 4 bytes in every version. Version 3 has version 2's fields in version 2's order; version 4
/// adds an opening's skew at the end of its record.
struct Layout {
  uint32_t version;
  size_t real;
  size_t small;
  explicit Layout(uint32_t v) : version(v), real(v >= 3 ? 4 : 8), small(v >= 3 ? 1 : 4) {}
  // Smallest records, to refuse impossible counts before allocating anything for them.
  size_t minNode() const {  // version 1: with the node's place and door
    return 4 + small + 3 * real + small + 4 + 4 + (version == 1 ? 4 + 3 * real : 0);
  }
  size_t opening() const {  // from version 2: with the door's place and pose in it; 4: and skew
    return 3 * real + small + (version >= 2 ? 4 + 3 * real : 0) + (version >= 4 ? real : 0);
  }
  size_t fingerprintEntry() const { return small + real; }
  size_t minEdge() const { return 3 * 4 + 2 * real + 4; }
  size_t landmark() const { return small + 4 * real + 4; }
};

std::string headerText(uint32_t version) {
  return std::string(kTopoMapMagic) + "\nversion " + std::to_string(version) + "\n";
}

// ---- encoding --------------------------------------------------------------------------------

/// Writes version 4: real numbers as float32 (the localizer computes in float32; poses, offsets
/// and widths within 6e-8 of their size, e.g. 1 um at 16 m), codes as u8.
class Writer : public laser_features::BinaryWriter {
 public:
  using BinaryWriter::BinaryWriter;
  void real(double v) { f32(static_cast<float>(v)); }
  /// An angle, normalized to (-pi, pi] and rounded inside it (within 2.4e-7 rad; NaN stays NaN).
  void angle(double a) { f32(laser_features::angleToFloat(normalizeAngle(a))); }
  void pose(const Pose2D& p) {
    real(p.x);
    real(p.y);
    angle(p.theta);
  }
};

void encodeNode(const TopoNode& node, Writer* w) {
  w->u32(node.id);
  w->u8(uint8_t(node.type));
  w->pose(node.pose);
  w->u8(node.explored ? 1u : 0u);
  w->u32(uint32_t(node.openings.size()));
  w->u32(uint32_t(node.fingerprint.entries.size()));
  for (const NodeOpening& o : node.openings) {
    w->angle(o.bearing);
    w->real(o.offset);
    w->real(o.width);
    w->u8(o.explored ? 1u : 0u);
    w->i32(o.place_id);
    w->pose(o.door_in_place);
    w->angle(o.skew);
  }
  for (const FingerprintEntry& e : node.fingerprint.entries) {
    w->u8(uint8_t(e.kind));
    w->angle(e.bearing);
  }
}

void encodeEdge(const TopoEdge& edge, Writer* w) {
  w->u32(edge.id);
  w->u32(edge.source);
  w->u32(edge.target);
  w->angle(edge.heading);
  w->real(edge.length);
  w->u32(uint32_t(edge.landmarks.size()));
  for (const EdgeLandmark& l : edge.landmarks) {
    w->u8(uint8_t(l.type));
    w->real(l.distance);
    w->real(l.lateral);
    w->angle(l.orientation);
    w->real(l.p_lmap);
    w->u32(l.observations);
  }
}

// ---- decoding --------------------------------------------------------------------------------

/// Reads the fields of any version, in the widths of its Layout.
class Reader : public laser_features::BinaryReader {
 public:
  Reader(const std::string& bytes, size_t begin, size_t end, const Layout& layout)
      : BinaryReader(bytes, begin, end), layout_(layout) {}
  const Layout& layout() const { return layout_; }
  double real(const char* what) { return layout_.real == 8 ? f64(what) : double(f32(what)); }
  uint32_t small(const char* what) { return layout_.small == 4 ? u32(what) : uint32_t(u8(what)); }
  /// An angle, which must lie in (-pi, pi].
  double angle(const char* what) {
    const double a = real(what);
    if (ok() && !(a > -kPi && a <= kPi)) {
      fail(std::string("angle ") + std::to_string(a) + " in " + what + " at byte " +
           std::to_string(position() - layout_.real) + " is not in (-pi, pi]");
    }
    return a;
  }
  Pose2D pose(const char* what) {
    Pose2D p;
    p.x = real(what);
    p.y = real(what);
    p.theta = angle(what);
    return p;
  }

 private:
  Layout layout_;
};

std::string nodeContext(size_t index, uint32_t id) {
  return "node #" + std::to_string(index) + " (id " + std::to_string(id) + ")";
}
std::string edgeContext(size_t index, uint32_t id) {
  return "edge #" + std::to_string(index) + " (id " + std::to_string(id) + ")";
}

bool validPlaceId(int32_t id, const std::string& where, std::string* error) {
  if (id >= -1) return true;
  *error = where + ": place id " + std::to_string(id) + " (expected -1 or a place id >= 0)";
  return false;
}

/// Reads one node record (in the reader's layout); false with the reader's error or `error` set.
bool decodeNode(Reader* in, size_t index, TopoNode* node, std::string* error) {
  const uint32_t version = in->layout().version;
  node->id = in->u32("a node id");
  const uint32_t type = in->small("a node type");
  node->pose = in->pose("a node pose");
  // Version 1: one place per node, behind its first opening (the door it was entered by).
  int32_t v1_place = -1;
  Pose2D v1_door;
  if (version == 1) {
    v1_place = in->i32("a node's place id");
    v1_door = in->pose("a node's door pose in its place");
  }
  const uint32_t flags = in->small("a node's flags");
  const uint32_t num_openings = in->u32("a node's opening count");
  const uint32_t num_entries = in->u32("a node's fingerprint size");
  if (!in->ok()) return false;
  const std::string where = nodeContext(index, node->id);
  if (type > uint32_t(NodeType::Start)) {
    *error = where + ": unknown node type " + std::to_string(type);
    return false;
  }
  node->type = NodeType(type);
  if (!validPlaceId(v1_place, where, error)) return false;
  if (v1_place >= 0 && num_openings == 0) {
    *error = where + ": links place " + std::to_string(v1_place) + " but has no opening (its door)";
    return false;
  }
  if (flags > 1u) {
    *error = where + ": unknown flags " + std::to_string(flags);
    return false;
  }
  node->explored = flags & 1u;
  const uint64_t needed = uint64_t(num_openings) * in->layout().opening() +
                         uint64_t(num_entries) * in->layout().fingerprintEntry();
  if (needed > in->remaining()) {
    *error = where + ": " + std::to_string(num_openings) + " openings and " + std::to_string(num_entries) +
             " fingerprint entries need " + std::to_string(needed) + " more bytes, the file has " +
             std::to_string(in->remaining()) + " (truncated?)";
    return false;
  }
  node->openings.resize(num_openings);
  for (size_t i = 0; i < node->openings.size(); ++i) {
    NodeOpening& o = node->openings[i];
    o.bearing = in->angle("an opening bearing");
    o.offset = in->real("an opening offset");
    o.width = in->real("an opening width");
    const uint32_t explored = in->small("an opening's flags");
    if (version >= 2) {
      o.place_id = in->i32("an opening's place id");
      o.door_in_place = in->pose("an opening's door pose in its place");
    } else if (i == 0) {
      o.place_id = v1_place;
      o.door_in_place = v1_door;
    }
    if (version >= 4) o.skew = in->angle("an opening's skew");  // before: bearings on the axes only
    if (!in->ok()) return false;
    if (!validPlaceId(o.place_id, where + ", opening " + std::to_string(i), error)) return false;
    if (o.width < 0.0) {
      *error = where + ", opening " + std::to_string(i) + ": negative width " + std::to_string(o.width);
      return false;
    }
    if (explored > 1u) {
      *error = where + ", opening " + std::to_string(i) + ": unknown flags " + std::to_string(explored);
      return false;
    }
    o.explored = explored & 1u;
  }
  node->fingerprint.entries.resize(num_entries);
  for (size_t i = 0; i < node->fingerprint.entries.size(); ++i) {
    FingerprintEntry& e = node->fingerprint.entries[i];
    const uint32_t kind = in->small("a fingerprint entry kind");
    e.bearing = in->angle("a fingerprint entry bearing");
    if (!in->ok()) return false;
    if (kind > uint32_t(FingerprintEntry::LineDirection)) {
      *error = where + ", fingerprint entry " + std::to_string(i) + ": unknown kind " + std::to_string(kind);
      return false;
    }
    e.kind = FingerprintEntry::Kind(kind);
  }
  return true;
}

/// Reads one edge record (its nodes are checked by the caller).
bool decodeEdge(Reader* in, size_t index, TopoEdge* edge, std::string* error) {
  edge->id = in->u32("an edge id");
  edge->source = in->u32("an edge source");
  edge->target = in->u32("an edge target");
  edge->heading = in->angle("an edge heading");
  edge->length = in->real("an edge length");
  const uint32_t num_landmarks = in->u32("an edge's landmark count");
  if (!in->ok()) return false;
  const std::string where = edgeContext(index, edge->id);
  if (edge->length < 0.0) {
    *error = where + ": negative length " + std::to_string(edge->length);
    return false;
  }
  const uint64_t needed = uint64_t(num_landmarks) * in->layout().landmark();
  if (needed > in->remaining()) {
    *error = where + ": " + std::to_string(num_landmarks) + " landmarks need " + std::to_string(needed) +
             " more bytes, the file has " + std::to_string(in->remaining()) + " (truncated?)";
    return false;
  }
  edge->landmarks.resize(num_landmarks);
  for (size_t i = 0; i < edge->landmarks.size(); ++i) {
    EdgeLandmark& l = edge->landmarks[i];
    const uint32_t type = in->small("a landmark type");
    l.distance = in->real("a landmark distance");
    l.lateral = in->real("a landmark lateral offset");
    l.orientation = in->angle("a landmark orientation");
    l.p_lmap = in->real("a landmark p_lmap");
    l.observations = in->u32("a landmark observation count");
    if (!in->ok()) return false;
    if (type > uint32_t(LandmarkType::Opening)) {
      *error = where + ", landmark " + std::to_string(i) + ": unknown landmark type " + std::to_string(type);
      return false;
    }
    l.type = LandmarkType(type);
    if (!(l.p_lmap >= 0.0 && l.p_lmap <= 1.0)) {
      *error = where + ", landmark " + std::to_string(i) + ": p_lmap " + std::to_string(l.p_lmap) +
               " is not in [0, 1]";
      return false;
    }
  }
  return true;
}

struct Decoded {
  std::map<uint32_t, TopoNode> nodes;
  std::map<uint32_t, TopoEdge> edges;
  uint32_t next_node_id = 0;
  uint32_t next_edge_id = 0;
};

/// Decodes the whole file; returns the problem (without the file's name), empty when valid.
// The magic line and the version line (checked before the checksum: a newer format may differ):
// an error, or none with the version and where the body starts.
std::string decodeHeader(const std::string& bytes, unsigned long* version_out, size_t* body_out) {
  const std::string magic = std::string(kTopoMapMagic) + "\n";
  if (bytes.compare(0, magic.size(), magic) != 0) {
    return std::string("not a topological map file (the first line is not '") + kTopoMapMagic + "')";
  }
  const size_t version_end = bytes.find('\n', magic.size());
  const std::string version_line =
      bytes.substr(magic.size(), version_end == std::string::npos ? 32 : version_end - magic.size());
  const bool version_prefix = version_line.compare(0, 8, "version ") == 0 && version_end != std::string::npos;
  const char* digits = version_prefix ? version_line.c_str() + 8 : "";
  char* digits_end = nullptr;
  const unsigned long version =
      std::isdigit(static_cast<unsigned char>(*digits)) ? std::strtoul(digits, &digits_end, 10) : 0;
  if (!version_prefix || digits_end == nullptr || *digits_end != '\0') {
    return "malformed version line '" + version_line + "' (expected 'version <n>')";
  }
  if (version > kTopoMapFormatVersion) {
    return "format version " + std::to_string(version) + " is newer than this build reads (" +
           std::to_string(kTopoMapFormatVersion) + "); update the software";
  }
  if (version < 1) {
    // Version 1 is the first format; an older number was never written by hybrid_slam.
    return "format version " + std::to_string(version) + " is older than this build reads (1.." +
           std::to_string(kTopoMapFormatVersion) + ") and has no migration; build the map again";
  }
  *version_out = version;
  *body_out = version_end + 1;
  return std::string();
}

// The nodes, then the edges (each on nodes read): into `out`, or the first error into `error`.
void decodeNodes(Reader* reader, Decoded* out, std::string* error_out) {
  Reader& in = *reader;
  std::string& error = *error_out;
  const uint32_t num_nodes = in.u32("the node count");
  const size_t min_node_bytes = in.layout().minNode();
  if (in.ok() && uint64_t(num_nodes) * min_node_bytes > in.remaining()) {
    error = std::to_string(num_nodes) + " nodes need at least " + std::to_string(uint64_t(num_nodes) * min_node_bytes) +
            " more bytes, the file has " + std::to_string(in.remaining()) + " (truncated?)";
  }
  for (uint32_t k = 0; k < num_nodes && in.ok() && error.empty(); ++k) {
    TopoNode node;
    if (!decodeNode(&in, k, &node, &error)) break;
    const uint32_t id = node.id;
    if (!out->nodes.emplace(id, std::move(node)).second) error = "node id " + std::to_string(id) + " appears twice";
  }
}

void decodeEdges(Reader* reader, Decoded* out, std::string* error_out) {
  Reader& in = *reader;
  std::string& error = *error_out;
  const uint32_t num_edges = error.empty() ? in.u32("the edge count") : 0;
  const size_t min_edge_bytes = in.layout().minEdge();
  if (in.ok() && error.empty() && uint64_t(num_edges) * min_edge_bytes > in.remaining()) {
    error = std::to_string(num_edges) + " edges need at least " + std::to_string(uint64_t(num_edges) * min_edge_bytes) +
            " more bytes, the file has " + std::to_string(in.remaining()) + " (truncated?)";
  }
  for (uint32_t k = 0; k < num_edges && in.ok() && error.empty(); ++k) {
    TopoEdge edge;
    if (!decodeEdge(&in, k, &edge, &error)) break;
    const std::string where = edgeContext(k, edge.id);
    if (edge.source == edge.target) {
      error = where + ": a self-loop on node " + std::to_string(edge.source);
    } else if (!out->nodes.count(edge.source) || !out->nodes.count(edge.target)) {
      error = where + ": refers to missing node " +
              std::to_string(out->nodes.count(edge.source) ? edge.target : edge.source);
    } else {
      const uint32_t id = edge.id;
      if (!out->edges.emplace(id, std::move(edge)).second) error = "edge id " + std::to_string(id) + " appears twice";
    }
  }
}

std::string decode(const std::string& bytes, Decoded* out) {
  unsigned long version = 0;
  size_t body = 0;
  const std::string header_error = decodeHeader(bytes, &version, &body);
  if (!header_error.empty()) return header_error;
  if (bytes.size() < body + 4) return "the file ends early (truncated?) before the checksum";
  const size_t checksum_at = bytes.size() - 4;

  Reader in(bytes, body, checksum_at, Layout(uint32_t(version)));
  std::string error;
  decodeNodes(&in, out, &error);
  decodeEdges(&in, out, &error);
  if (error.empty()) {
    out->next_node_id = in.u32("the next node id");
    out->next_edge_id = in.u32("the next edge id");
  }
  if (in.ok() && error.empty()) {
    // addNode / addEdge hand out the next ids: they must not collide with stored ones.
    if (!out->nodes.empty() && out->next_node_id <= out->nodes.rbegin()->first) {
      error = "next node id " + std::to_string(out->next_node_id) + " is not above node id " +
              std::to_string(out->nodes.rbegin()->first);
    } else if (!out->edges.empty() && out->next_edge_id <= out->edges.rbegin()->first) {
      error = "next edge id " + std::to_string(out->next_edge_id) + " is not above edge id " +
              std::to_string(out->edges.rbegin()->first);
    } else if (in.remaining() != 0) {
      error = std::to_string(in.remaining()) + " unexpected bytes before the checksum";
    }
  }
  if (!in.ok()) error = in.error();

  // The checksum first (a truncated or damaged file fails both; report the structure as a hint).
  Reader trailer(bytes, checksum_at, bytes.size(), in.layout());
  const uint32_t stored = trailer.u32("the checksum");
  const uint32_t computed = laser_features::crc32(bytes.data(), checksum_at);
  if (stored != computed) {
    return "checksum mismatch (stored " + std::to_string(stored) + ", computed " + std::to_string(computed) +
           "): the file is corrupt or truncated" + (error.empty() ? std::string() : "; " + error);
  }
  return error;
}

IoResult loadFailure(const std::string& name, const std::string& what) {
  return {false, "cannot load topological map from '" + name + "': " + what};
}

}  // namespace

std::string encodeMap(const TopologicalMap& map) {
  std::string out = headerText(kTopoMapFormatVersion);
  Writer w(&out);
  w.u32(uint32_t(map.nodeCount()));
  for (const auto& entry : map.nodes()) encodeNode(entry.second, &w);
  w.u32(uint32_t(map.edgeCount()));
  for (const auto& entry : map.edges()) encodeEdge(entry.second, &w);
  w.u32(map.nextNodeId());
  w.u32(map.nextEdgeId());
  w.u32(laser_features::crc32(out.data(), out.size()));
  return out;
}

IoResult decodeMap(const std::string& bytes, const std::string& name, TopologicalMap* map) {
  Decoded decoded;
  const std::string problem = decode(bytes, &decoded);
  if (!problem.empty()) return loadFailure(name, problem);
  // All or nothing: only a fully valid file reaches the map.
  map->assign(std::move(decoded.nodes), std::move(decoded.edges), decoded.next_node_id, decoded.next_edge_id);
  return {};
}

IoResult saveMap(const TopologicalMap& map, const std::string& path) {
  const std::string bytes = encodeMap(map);
  // Never write a file that loading would refuse (e.g. a NaN or a negative width in memory).
  Decoded check;
  const std::string problem = decode(bytes, &check);
  if (!problem.empty()) return {false, "cannot save topological map to '" + path + "': the map is invalid: " + problem};
  std::string error;
  if (!laser_features::writeFileAtomically(path, bytes, &error)) {
    return {false, "cannot save topological map to '" + path + "': " + error};
  }
  return {};
}

IoResult loadMap(const std::string& path, TopologicalMap* map) {
  std::string bytes, error;
  if (!laser_features::readWholeFile(path, &bytes, &error)) return loadFailure(path, error);
  return decodeMap(bytes, path, map);
}

}  // namespace pomdp_topo
