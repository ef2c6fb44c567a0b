// Saving and loading all places (DESIGN.md: written atomically, versioned; a corrupt or newer file
// is refused with a clear error and the maps in memory are kept).
//
// File format, version 3: two text lines, then little-endian binary (u32: 4-byte unsigned integer,
// f32 / f64: IEEE-754 binary32 / binary64):
//
//   "hybrid_slam_places\n"              magic line
//   "version 3\n"                       format version, decimal
//   u32 place_count, u32 next_id        next_id: the id the next created place gets
//   per place:
//     u32 id
//     u32 flags                         bit 0: a relocation is pending; bit 1: compact record
//     u32 line_count n, u32 door_count d
//     compact record (bit 1 set: a closed place, unless store_joint_covariance); with the 16 bytes
//     above, 64 + 28 n + 40 d bytes:
//       f32 x, y, theta                 display pose of the place frame in `map`
//       f32 x, y, theta                 robot pose in the place frame (state, eq. 6)
//       f32 c00, c01, c02, c11, c12, c22                 the robot's 3x3 marginal covariance (upper triangle)
//       n x { f32 alpha, r, s_start, s_end, c_aa, c_ar, c_rr }   (28 bytes: the line; its extent as the
//                                       signed positions of its end points along the line's direction
//                                       t = (-sin alpha, cos alpha), each end point being r n + s t with
//                                       n = (cos alpha, sin alpha); its 2x2 marginal covariance, upper triangle)
//       d x { u32 door_id, f32 x, y, theta, c00, c01, c02, c11, c12, c22 }            (40 bytes)
//     full record (bit 1 clear: the active place, or every place with store_joint_covariance); with
//     the 16 bytes above, 64 + 48 n + 76 d + 4 N (N + 1) bytes:
//       f64 x, y, theta                 display pose
//       f64 x, y, theta                 robot pose
//       n x { f64 alpha, r, extent_start x, y, extent_end x, y }
//       d x { u32 door_id, f64 x, y, theta, f64 c00, c01, c02, c11, c12, c22 }   (door pose, upper
//                                       triangle of its covariance)
//       f64 x (N (N + 1) / 2)           the full covariance P (eq. 6), N = 3 + 2 n, as its lower
//                                       triangle row by row: P(0,0), P(1,0), P(1,1), P(2,0), ...
//   u32 CRC-32 (IEEE 802.3 polynomial, as zlib's crc32) of every byte before it
//
// Older versions, still read: in version 2 a place is u32 id, f64 display pose, u32 flags, n, d,
// f64 robot pose, then the record; its compact record has no poses and stores the extent's end
// points (f32 x, y each: 36 bytes a line). Version 1 is version 2 with full records only (flags bit
// 1 never set).
//
// A compact record keeps what relocation and missions use: the lines, their extents and marginals,
// the robot pose, the doors. Loading it rebuilds P block-diagonal (see decodeCompactBody in
// persistence.cpp): the lines' cross-covariances are gone, each line's marginal is kept. Precision
// of its float32 numbers (7 significant digits), against the EKF's millimetres and 1e-4 rad:
// angles within 2.4e-7 rad (written inside (-pi, pi] after rounding); lengths and positions within
// 6e-8 of their size (1 um at 16 m, 4 um at 64 m). An extent's end point is read back as its
// projection onto the stored line: the along-line position round-trips within float rounding;
// the distance of the end point from the line (the line's drift since the extent last grew; at
// most 0.5 mm on institute) is dropped. The EKF uses an extent only along its line (overlap of an
// observed segment, growing the extent) and, at a 10 m scale, for its distance from the robot.
//
// Covariances are stored as triangles, so they are symmetric by construction; a flipped byte
// anywhere fails the checksum. Loading also refuses: a wrong magic line, a newer or unknown version,
// unknown flags, a file that ends early or has bytes after the checksum, non-finite numbers, angles
// outside (-pi, pi], negative r, duplicate ids, and covariances that are not positive semi-definite
// (within 1e-9 of their largest eigenvalue for f64, 1e-6 for f32).
#pragma once

#include "ekf_local_map/place_maps.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ekf_local_map {

constexpr uint32_t kPlacesFormatVersion = 3;
constexpr uint32_t kPlacesOldestFormatVersion = 1;  // still read
constexpr const char* kPlacesMagic = "hybrid_slam_places";

struct IoResult {
  bool ok = true;
  std::string error;  // names the file and what is wrong
  explicit operator bool() const { return ok; }
};

/// How closed places are written (the node's ~store_joint_covariance; config/ekf_local_map.yaml).
struct PlacesSaveOptions {
  // bool, default false: also store each closed place's full joint covariance (f64, (N^2 + N) / 2
  // numbers for N = 3 + 2 lines: the bulk of a map); false stores the compact record (float32 lines,
  // extents, marginal covariances, robot pose, doors), which is what relocation and missions use.
  bool store_joint_covariance = false;
};

/// Writes all places to `path` atomically: `path`.tmp is written and fsync'ed, then renamed over
/// `path` (and the directory fsync'ed). On failure `path` is untouched and no .tmp is left.
IoResult savePlaces(const PlaceMaps& maps, const std::string& path,
                    const PlacesSaveOptions& options = PlacesSaveOptions());

/// Reads places from `path` into a temporary and swaps it into `maps` only when the whole file is
/// valid; on failure `maps` is untouched. Loaded places take `maps`' current parameters, and no
/// place is active afterwards. Reads versions kPlacesOldestFormatVersion..kPlacesFormatVersion.
IoResult loadPlaces(const std::string& path, PlaceMaps* maps);

/// The encoded file contents (what savePlaces writes). The active place, if any, is always written
/// with its joint covariance: it is a filter in progress, and a save must not change it.
std::string encodePlaces(const PlaceMaps& maps, const PlacesSaveOptions& options = PlacesSaveOptions());
/// Decodes file contents; `name` is used in error messages.
IoResult decodePlaces(const std::string& bytes, const std::string& name, PlaceMaps* maps);

/// Storage size of each place as written by savePlaces with `options`, and in both record kinds.
struct PlaceStorage {
  uint32_t id = 0;
  size_t lines = 0;
  size_t doors = 0;
  bool compact = false;    // the record savePlaces writes for this place is the compact one
  size_t bytes = 0;        // that record: state, lines, extents, doors, covariance(s)
  size_t compact_bytes = 0;  // the compact record (f32 marginals): 64 + 28 n + 40 d
  size_t full_bytes = 0;     // the full record (f64, joint covariance): 64 + 48 n + 76 d + 4 N (N + 1)
  size_t line_bytes = 0;   // of `bytes`, the lines with their extents (and marginals, if compact)
  double area_m2 = 0.0;    // bounding box of the line extents
  double bytes_per_m2 = 0.0;
  double line_bytes_per_m2 = 0.0;
};
std::vector<PlaceStorage> storageStats(const PlaceMaps& maps, const PlacesSaveOptions& options = PlacesSaveOptions());

}  // namespace ekf_local_map
