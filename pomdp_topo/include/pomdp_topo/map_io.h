// Saving and loading the topological map (DESIGN.md: written atomically, versioned; a corrupt or
// newer file is refused with a clear error and the map in memory is kept).
//
// File format, version 4: two text lines, then little-endian binary (u8 / u32: 1- / 4-byte unsigned
// integer, i32: 4-byte two's complement, f32: IEEE-754 binary32):
//
//   "hybrid_slam_topological_map\n"     magic line
//   "version 4\n"                       format version, decimal
//   u32 node_count
//   node_count x {                      26 bytes + 33 an opening + 5 a fingerprint entry
//     u32 id, u8 type                   type: NodeType (0 door, 1 junction, 2 hallway end, 3 place, 4 start)
//     f32 x, y, theta                   display pose in the map frame
//     u8 flags                          bit 0: explored
//     u32 opening_count o, u32 fingerprint_count f
//     o x { f32 bearing, offset, width, u8 flags,      flags bit 0: explored
//           i32 place_id,                              the place behind the door, -1: none
//           f32 x, y, theta,                           door_in_place: the door's pose in that place
//           f32 skew }                                 NodeOpening::skew (direction = bearing + skew)
//     f x { u8 kind, f32 bearing }               kind: FingerprintEntry::Kind (0 corner, 1 opening,
//                                                     2 line direction), in the stored order
//   }
//   u32 edge_count
//   edge_count x {                      24 bytes + 21 a landmark
//     u32 id, source, target
//     f32 heading, length
//     u32 landmark_count l
//     l x { u8 type, f32 distance, lateral, orientation, p_lmap, u32 observations }
//                                       type: LandmarkType (0 corner, 1 opening), in the stored order
//   }
//   u32 next_node_id, u32 next_edge_id
//   u32 CRC-32 (IEEE 802.3 polynomial, as zlib's crc32) of every byte before it
//
// Precision: float32 keeps 7 significant digits: positions, offsets, widths, lengths and landmark
// distances within 6e-8 of their size (1 um at 16 m), angles within 2.4e-7 rad, p_lmap within 3e-8.
// That is far inside what is used: the localizer matches landmarks in float32 and with sigmas of
// decimetres (match_sigma_along, match_sigma_lateral), fingerprints match within 0.3 rad
// (fingerprint_tolerance), and a door's pose in its place is metric (millimetres and 1e-4 rad
// would do). A map read back and saved again is the same bit for bit.
//
// Angles are written normalized to (-pi, pi] and stay inside it after rounding. Loading refuses,
// naming the file and the problem: a wrong magic line, a newer or unknown version, a checksum
// mismatch (a flipped byte anywhere), a file that ends early or has bytes after the body,
// non-finite numbers, angles outside (-pi, pi], a negative edge length or opening width, p_lmap
// outside [0, 1], a place_id below -1, unknown types, kinds or flag bits, duplicate node or edge
// ids, an edge referring to a missing node, a self-loop, and next ids not above every id in use.
// saveMap refuses (and writes nothing) a map that loading would refuse (a number beyond float32's
// range among them).
//
// Older versions, still read: version 3 is version 4 without an opening's skew (read as 0: until
// then a wing's doors were stored across its bin). Version 2 is version 3 with f64 for every real
// number and u32 for every u8 (node 44 bytes, opening 56, fingerprint entry 12, edge 32, landmark
// 40). Version 1 (until
// stop 19) had one place per node: i32 place_id and f64 x, y, theta door_in_place after the node's
// pose, and openings without them; the node's place becomes its first opening's (the door it was
// entered by, which linking put first).
#pragma once

#include "pomdp_topo/topological_map.h"

#include <cstdint>
#include <string>

namespace pomdp_topo {

constexpr uint32_t kTopoMapFormatVersion = 4;
constexpr const char* kTopoMapMagic = "hybrid_slam_topological_map";

struct IoResult {
  bool ok = true;
  std::string error;  // names the file and what is wrong
  explicit operator bool() const { return ok; }
};

/// The encoded file contents (what saveMap writes).
std::string encodeMap(const TopologicalMap& map);

/// Decodes file contents into `map`, all or nothing: on failure `map` is untouched. `name` is used
/// in error messages. On success the map's revision is bumped (TopologicalMap::assign).
IoResult decodeMap(const std::string& bytes, const std::string& name, TopologicalMap* map);

/// Writes the map to `path` atomically (laser_features::writeFileAtomically: `path`.tmp, fsync,
/// rename). On failure `path` is untouched and no .tmp is left; an invalid map (one loadMap would
/// refuse) is not written.
IoResult saveMap(const TopologicalMap& map, const std::string& path);

/// Reads `path` and decodes it into `map`, all or nothing.
IoResult loadMap(const std::string& path, TopologicalMap* map);

}  // namespace pomdp_topo
