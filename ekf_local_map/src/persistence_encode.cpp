// Saving places: each place's record encoded (full, or compact in float32), encodePlaces, savePlaces,
// and storageStats, which sizes both records of every place. Loading them: persistence.cpp. The
// format: persistence.h.
#include "ekf_local_map/persistence.h"
#include "persistence_format.h"

#include "laser_features/file_io.h"

#include <string>
#include <vector>

namespace ekf_local_map {

namespace {

std::string headerText(uint32_t version) {
  return std::string(kPlacesMagic) + "\nversion " + std::to_string(version) + "\n";
}

// ---- encoding --------------------------------------------------------------------------------

class Writer : public laser_features::BinaryWriter {
 public:
  using BinaryWriter::BinaryWriter;
  void pose(const Pose2D& p) {
    f64(p.x);
    f64(p.y);
    f64(p.theta);
  }
  void poseF32(const Pose2D& p) {
    f32(static_cast<float>(p.x));
    f32(static_cast<float>(p.y));
    f32(laser_features::angleToFloat(p.theta));
  }
  /// The upper triangle of a symmetric matrix, row by row, as float32.
  template <typename Matrix>
  void upperTriangleF32(const Matrix& M) {
    for (Eigen::Index r = 0; r < M.rows(); ++r)
      for (Eigen::Index c = r; c < M.cols(); ++c) f32(static_cast<float>(M(r, c)));
  }
};

/// The full record (version 1's): f64 lines with extents, doors and the joint covariance P.
void encodeFullBody(const Place& place, Writer* out) {
  Writer& w = *out;
  const StochasticMap& map = place.map;
  for (size_t i = 0; i < map.numLines(); ++i) {
    const MapLine line = map.line(i);
    w.f64(line.line.alpha);
    w.f64(line.line.r);
    w.f64(line.extent_start.x());
    w.f64(line.extent_start.y());
    w.f64(line.extent_end.x());
    w.f64(line.extent_end.y());
  }
  for (const auto& entry : place.doors) {
    const Door& door = entry.second;
    w.u32(door.id);
    w.pose(door.pose);
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) w.f64(door.cov(r, c));
  }
  const Eigen::MatrixXd P = map.covariance();
  for (Eigen::Index r = 0; r < P.rows(); ++r)
    for (Eigen::Index c = 0; c <= r; ++c) w.f64(P(r, c));
}

/// The compact record: what relocation and missions use, in float32, marginals only.
void encodeCompactBody(const Place& place, Writer* out) {
  Writer& w = *out;
  const StochasticMap& map = place.map;
  w.poseF32(place.display_pose);
  w.poseF32(map.robotPose());
  w.upperTriangleF32(map.robotCovariance());
  for (size_t i = 0; i < map.numLines(); ++i) {
    const MapLine line = map.line(i);
    // The line as it will be read back; the extent's end points as positions along it, so that
    // the reader rebuilds each as the original's projection onto the stored line.
    Line stored;
    stored.alpha = laser_features::angleToFloat(line.line.alpha);
    stored.r = static_cast<float>(line.line.r);
    w.f32(static_cast<float>(stored.alpha));
    w.f32(static_cast<float>(stored.r));
    w.f32(static_cast<float>(stored.direction().dot(line.extent_start)));
    w.f32(static_cast<float>(stored.direction().dot(line.extent_end)));
    w.upperTriangleF32(line.line.cov);  // the marginal: the 2x2 block of P
  }
  for (const auto& entry : place.doors) {
    const Door& door = entry.second;
    w.u32(door.id);
    w.poseF32(door.pose);
    w.upperTriangleF32(door.cov);
  }
}

void encodePlace(const Place& place, bool compact, std::string* out) {
  Writer w(out);
  const StochasticMap& map = place.map;
  w.u32(place.id);
  w.u32((map.relocationPending() ? kFlagRelocationPending : 0u) | (compact ? kFlagCompact : 0u));
  w.u32(uint32_t(map.numLines()));
  w.u32(uint32_t(place.doors.size()));
  if (compact) {
    encodeCompactBody(place, &w);
  } else {
    w.pose(place.display_pose);
    w.pose(map.robotPose());
    encodeFullBody(place, &w);
  }
}

/// The active place keeps its joint covariance (a filter in progress); closed places are compact
/// unless the options ask for the joint covariance.
bool writeCompact(const PlaceMaps& maps, uint32_t id, const PlacesSaveOptions& options) {
  return !options.store_joint_covariance && maps.activeId() != id;
}

}  // namespace

std::string encodePlaces(const PlaceMaps& maps, const PlacesSaveOptions& options) {
  std::string out = headerText(kPlacesFormatVersion);
  Writer w(&out);
  w.u32(uint32_t(maps.size()));
  w.u32(maps.nextId());
  for (const auto& entry : maps.places()) encodePlace(entry.second, writeCompact(maps, entry.first, options), &out);
  w.u32(laser_features::crc32(out.data(), out.size()));
  return out;
}

IoResult savePlaces(const PlaceMaps& maps, const std::string& path, const PlacesSaveOptions& options) {
  std::string error;
  if (!laser_features::writeFileAtomically(path, encodePlaces(maps, options), &error)) {
    return {false, "cannot save places to '" + path + "': " + error};
  }
  return {};
}

std::vector<PlaceStorage> storageStats(const PlaceMaps& maps, const PlacesSaveOptions& options) {
  std::vector<PlaceStorage> stats;
  for (const auto& entry : maps.places()) {
    const StochasticMap& map = entry.second.map;
    PlaceStorage s;
    s.id = entry.first;
    s.lines = map.numLines();
    s.doors = entry.second.doors.size();
    s.compact = writeCompact(maps, entry.first, options);
    std::string compact, full;
    encodePlace(entry.second, true, &compact);
    encodePlace(entry.second, false, &full);
    s.compact_bytes = compact.size();
    s.full_bytes = full.size();
    s.bytes = s.compact ? s.compact_bytes : s.full_bytes;
    s.line_bytes = map.numLines() * (s.compact ? kCompactLineBytes : kLineRecordBytes);
    if (map.numLines() > 0) {
      Eigen::Vector2d lo = map.line(0).extent_start, hi = lo;
      for (size_t i = 0; i < map.numLines(); ++i) {
        const MapLine line = map.line(i);
        lo = lo.cwiseMin(line.extent_start).cwiseMin(line.extent_end);
        hi = hi.cwiseMax(line.extent_start).cwiseMax(line.extent_end);
      }
      s.area_m2 = (hi - lo).prod();
    }
    if (s.area_m2 > 0.0) {
      s.bytes_per_m2 = double(s.bytes) / s.area_m2;
      s.line_bytes_per_m2 = double(s.line_bytes) / s.area_m2;
    }
    stats.push_back(s);
  }
  return stats;
}

}  // namespace ekf_local_map
