// Saving and loading all places (DESIGN.md: written atomically, versioned; a corrupt or newer file
// is refused with a clear error and the maps in memory are kept).
//
// File format, version 1: two text lines, then little-endian binary (u32: 4-byte unsigned integer,
// f64: IEEE-754 binary64):
//
//   "hybrid_slam_places\n"              magic line
//   "version 1\n"                       format version, decimal
//   u32 place_count, u32 next_id        next_id: the id the next created place gets
//   per place:
//     u32 id
//     f64 x, y, theta                   display pose of the place frame in `map`
//     u32 flags                         bit 0: a relocation is pending
//     u32 line_count n, u32 door_count d
//     f64 x, y, theta                   robot pose in the place frame (state, eq. 6)
//     n x { f64 alpha, r, extent_start x, y, extent_end x, y }
//     d x { u32 door_id, f64 x, y, theta, f64 c00, c01, c02, c11, c12, c22 }   (door pose, upper
//                                       triangle of its covariance)
//     f64 x (N (N + 1) / 2)             the full covariance P (eq. 6), N = 3 + 2 n, as its lower
//                                       triangle row by row: P(0,0), P(1,0), P(1,1), P(2,0), ...
//   u32 CRC-32 (IEEE 802.3 polynomial, as zlib's crc32) of every byte before it
//
// Covariances are stored as triangles, so they are symmetric by construction; a flipped byte
// anywhere fails the checksum. Loading also refuses: a wrong magic line, a newer or unknown version,
// a file that ends early or has bytes after the checksum, non-finite numbers, angles outside
// (-pi, pi], negative r, duplicate ids, and covariances that are not positive semi-definite.
#pragma once

#include "ekf_local_map/place_maps.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ekf_local_map {

constexpr uint32_t kPlacesFormatVersion = 1;
constexpr const char* kPlacesMagic = "hybrid_slam_places";

struct IoResult {
  bool ok = true;
  std::string error;  // names the file and what is wrong
  explicit operator bool() const { return ok; }
};

/// Writes all places to `path` atomically: `path`.tmp is written and fsync'ed, then renamed over
/// `path` (and the directory fsync'ed). On failure `path` is untouched and no .tmp is left.
IoResult savePlaces(const PlaceMaps& maps, const std::string& path);

/// Reads places from `path` into a temporary and swaps it into `maps` only when the whole file is
/// valid; on failure `maps` is untouched. Loaded places take `maps`' current parameters, and no
/// place is active afterwards.
IoResult loadPlaces(const std::string& path, PlaceMaps* maps);

/// The encoded file contents (what savePlaces writes).
std::string encodePlaces(const PlaceMaps& maps);
/// Decodes file contents; `name` is used in error messages.
IoResult decodePlaces(const std::string& bytes, const std::string& name, PlaceMaps* maps);

/// Storage size of each place as written by savePlaces.
struct PlaceStorage {
  uint32_t id = 0;
  size_t lines = 0;
  size_t bytes = 0;        // the place's record: state, lines, extents, doors, full covariance
  size_t line_bytes = 0;   // of which the lines with their extents only (48 bytes per line)
  double area_m2 = 0.0;    // bounding box of the line extents
  double bytes_per_m2 = 0.0;
  double line_bytes_per_m2 = 0.0;
};
std::vector<PlaceStorage> storageStats(const PlaceMaps& maps);

}  // namespace ekf_local_map
