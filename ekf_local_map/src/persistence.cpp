#include "ekf_local_map/persistence.h"

#include "laser_features/file_io.h"

#include <Eigen/Eigenvalues>


#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

namespace ekf_local_map {

namespace {

constexpr size_t kLineRecordBytes = 6 * 8;
constexpr size_t kDoorRecordBytes = 4 + 9 * 8;

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
};

void encodePlace(const Place& place, std::string* out) {
  Writer w(out);
  const StochasticMap& map = place.map;
  w.u32(place.id);
  w.pose(place.display_pose);
  w.u32(map.relocationPending() ? 1u : 0u);
  w.u32(uint32_t(map.numLines()));
  w.u32(uint32_t(place.doors.size()));
  w.pose(map.robotPose());
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

// ---- decoding --------------------------------------------------------------------------------

class Reader : public laser_features::BinaryReader {
 public:
  using BinaryReader::BinaryReader;
  Pose2D pose(const char* what) {
    Pose2D p;
    p.x = f64(what);
    p.y = f64(what);
    p.theta = f64(what);
    return p;
  }
};

bool normalizedAngle(double a) { return a > -laser_features::kPi - 1e-12 && a <= laser_features::kPi + 1e-12; }

/// Positive semi-definite within rounding (the eigenvalues of a saved P are >= 0 up to ~1e-15 of its norm).
bool positiveSemiDefinite(const Eigen::MatrixXd& M) {
  if (M.size() == 0) return true;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(M, Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) return false;
  const double scale = std::max(eigen.eigenvalues().cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  return eigen.eigenvalues().minCoeff() >= -1e-9 * scale;
}

std::string placeContext(size_t index, uint32_t id) {
  return "place #" + std::to_string(index) + " (id " + std::to_string(id) + ")";
}

/// Reads one place record; returns false with the reader's or `error`'s message.
bool decodePlace(Reader* in, size_t index, const StochasticMapParams& params, Place* place, std::string* error) {
  place->id = in->u32("a place id");
  const std::string where = placeContext(index, place->id);
  place->display_pose = in->pose("a place's display pose");
  const uint32_t flags = in->u32("a place's flags");
  const uint32_t num_lines = in->u32("a place's line count");
  const uint32_t num_doors = in->u32("a place's door count");
  if (!in->ok()) return false;
  if (flags > 1u) {
    *error = where + ": unknown flags " + std::to_string(flags);
    return false;
  }
  // Refuse impossible counts before allocating anything for them.
  const uint64_t n = 3 + 2 * uint64_t(num_lines);
  const uint64_t needed = 24 + uint64_t(num_lines) * kLineRecordBytes + uint64_t(num_doors) * kDoorRecordBytes +
                          n * (n + 1) / 2 * 8;
  if (needed > in->remaining()) {
    *error = where + ": " + std::to_string(num_lines) + " lines and " + std::to_string(num_doors) +
             " doors need " + std::to_string(needed) + " more bytes, the file has " +
             std::to_string(in->remaining()) + " (truncated?)";
    return false;
  }
  const Pose2D robot = in->pose("the robot pose");
  std::vector<MapLine> lines(num_lines);
  for (MapLine& line : lines) {
    line.line.alpha = in->f64("a line");
    line.line.r = in->f64("a line");
    line.extent_start.x() = in->f64("a line extent");
    line.extent_start.y() = in->f64("a line extent");
    line.extent_end.x() = in->f64("a line extent");
    line.extent_end.y() = in->f64("a line extent");
  }
  for (uint32_t d = 0; d < num_doors; ++d) {
    Door door;
    door.id = in->u32("a door id");
    door.pose = in->pose("a door pose");
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) door.cov(r, c) = door.cov(c, r) = in->f64("a door covariance");
    if (!in->ok()) return false;
    if (!place->doors.emplace(door.id, door).second) {
      *error = where + ": door id " + std::to_string(door.id) + " appears twice";
      return false;
    }
    if (!normalizedAngle(door.pose.theta) || !positiveSemiDefinite(door.cov)) {
      *error = where + ", door " + std::to_string(door.id) +
               ": angle not in (-pi, pi] or covariance not positive semi-definite";
      return false;
    }
  }
  Eigen::MatrixXd P(n, n);
  for (Eigen::Index r = 0; r < Eigen::Index(n); ++r)
    for (Eigen::Index c = 0; c <= r; ++c) P(r, c) = P(c, r) = in->f64("the covariance");
  if (!in->ok()) return false;

  if (!normalizedAngle(robot.theta)) {
    *error = where + ": robot heading " + std::to_string(robot.theta) + " not in (-pi, pi]";
    return false;
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    if (!normalizedAngle(lines[i].line.alpha) || lines[i].line.r < 0.0) {
      *error = where + ", line " + std::to_string(i) + ": (alpha, r) = (" + std::to_string(lines[i].line.alpha) +
               ", " + std::to_string(lines[i].line.r) + ") is not canonical (alpha in (-pi, pi], r >= 0)";
      return false;
    }
  }
  if ((P.diagonal().array() < 0.0).any() || !positiveSemiDefinite(P)) {
    *error = where + ": the covariance (" + std::to_string(n) + "x" + std::to_string(n) +
             ") is not positive semi-definite";
    return false;
  }
  place->map = StochasticMap(params);
  place->map.setState(robot, lines, P, flags & 1u);
  return true;
}

IoResult failure(const std::string& name, const std::string& what) {
  return {false, "cannot load places from '" + name + "': " + what};
}

}  // namespace

std::string encodePlaces(const PlaceMaps& maps) {
  std::string out = headerText(kPlacesFormatVersion);
  Writer w(&out);
  w.u32(uint32_t(maps.size()));
  w.u32(maps.nextId());
  for (const auto& entry : maps.places()) encodePlace(entry.second, &out);
  w.u32(laser_features::crc32(out.data(), out.size()));
  return out;
}

IoResult decodePlaces(const std::string& bytes, const std::string& name, PlaceMaps* maps) {
  // Magic line, then the version line (checked before the checksum: a newer format may differ).
  const std::string magic = std::string(kPlacesMagic) + "\n";
  if (bytes.compare(0, magic.size(), magic) != 0) {
    return failure(name, std::string("not a places file (the first line is not '") + kPlacesMagic + "')");
  }
  const size_t version_end = bytes.find('\n', magic.size());
  const std::string version_line =
      bytes.substr(magic.size(), version_end == std::string::npos ? 32 : version_end - magic.size());
  const bool version_prefix = version_line.compare(0, 8, "version ") == 0 && version_end != std::string::npos;
  const char* digits = version_prefix ? version_line.c_str() + 8 : "";
  char* digits_end = nullptr;
  const unsigned long version = std::isdigit(static_cast<unsigned char>(*digits)) ? std::strtoul(digits, &digits_end, 10) : 0;
  if (!version_prefix || digits_end == nullptr || *digits_end != '\0') {
    return failure(name, "malformed version line '" + version_line + "' (expected 'version <n>')");
  }
  if (version > kPlacesFormatVersion) {
    return failure(name, "format version " + std::to_string(version) + " is newer than this build reads (" +
                             std::to_string(kPlacesFormatVersion) + "); update the software");
  }
  if (version < kPlacesFormatVersion) {
    // Version 1 is the first format; an older number was never written by hybrid_slam.
    return failure(name, "format version " + std::to_string(version) + " is older than this build reads (" +
                             std::to_string(kPlacesFormatVersion) + ") and has no migration; build the map again");
  }
  const size_t body = version_end + 1;
  if (bytes.size() < body + 4) return failure(name, "the file ends early (truncated?) before the checksum");
  const size_t checksum_at = bytes.size() - 4;

  PlaceMaps loaded(maps->params());
  std::map<uint32_t, Place> places;
  Reader in(bytes, body, checksum_at);
  const uint32_t count = in.u32("the place count");
  const uint32_t next_id = in.u32("the next place id");
  std::string error;
  for (uint32_t k = 0; k < count && in.ok() && error.empty(); ++k) {
    Place place{0, {}, StochasticMap(StochasticMapParams{}), {}};
    if (!decodePlace(&in, k, maps->params(), &place, &error)) break;
    const uint32_t id = place.id;
    if (!places.emplace(id, std::move(place)).second) error = "place id " + std::to_string(id) + " appears twice";
  }
  // What the structure says is wrong, if anything (reported with the checksum result: a
  // truncated file fails both).
  if (!in.ok()) {
    error = in.error();
  } else if (error.empty() && in.remaining() != 0) {
    error = std::to_string(in.remaining()) + " unexpected bytes before the checksum";
  }
  Reader trailer(bytes, checksum_at, bytes.size());
  const uint32_t stored = trailer.u32("the checksum");
  const uint32_t computed = laser_features::crc32(bytes.data(), checksum_at);
  if (stored != computed) {
    return failure(name, "checksum mismatch (stored " + std::to_string(stored) + ", computed " +
                             std::to_string(computed) + "): the file is corrupt or truncated" +
                             (error.empty() ? std::string() : "; " + error));
  }
  if (!error.empty()) return failure(name, error);

  loaded.assign(std::move(places), next_id);
  maps->swap(loaded);  // all or nothing
  return {};
}

IoResult savePlaces(const PlaceMaps& maps, const std::string& path) {
  std::string error;
  if (!laser_features::writeFileAtomically(path, encodePlaces(maps), &error)) {
    return {false, "cannot save places to '" + path + "': " + error};
  }
  return {};
}

IoResult loadPlaces(const std::string& path, PlaceMaps* maps) {
  std::string bytes, error;
  if (!laser_features::readWholeFile(path, &bytes, &error)) return failure(path, error);
  return decodePlaces(bytes, path, maps);
}

std::vector<PlaceStorage> storageStats(const PlaceMaps& maps) {
  std::vector<PlaceStorage> stats;
  for (const auto& entry : maps.places()) {
    const StochasticMap& map = entry.second.map;
    PlaceStorage s;
    s.id = entry.first;
    s.lines = map.numLines();
    std::string record;
    encodePlace(entry.second, &record);
    s.bytes = record.size();
    s.line_bytes = map.numLines() * kLineRecordBytes;
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
