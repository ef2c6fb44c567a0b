// Loading places: each place's record decoded and checked, decodePlaces and loadPlaces. Saving them:
// persistence_encode.cpp. The format: persistence.h.
#include "ekf_local_map/persistence.h"
#include "persistence_format.h"

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

// Tolerances of the positive semi-definite check, relative to the largest eigenvalue: rounding of
// f64 numbers, and of f32 ones (float32's epsilon is 1.2e-7).
constexpr double kPsdToleranceF64 = 1e-9;
constexpr double kPsdToleranceF32 = 1e-6;

// ---- decoding --------------------------------------------------------------------------------

/// The point at signed position `s` along `line` (direction t = (-sin alpha, cos alpha)) from the
/// foot of its normal: r n + s t. The compact record's extents are rebuilt with it.
Eigen::Vector2d pointOnLine(const Line& line, double s) { return line.r * line.normal() + s * line.direction(); }

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
  Pose2D poseF32(const char* what) {
    Pose2D p;
    p.x = f32(what);
    p.y = f32(what);
    p.theta = f32(what);
    return p;
  }
  /// A symmetric N x N matrix from its upper triangle in float32, row by row.
  template <int N>
  Eigen::Matrix<double, N, N> symmetricF32(const char* what) {
    Eigen::Matrix<double, N, N> M;
    for (int r = 0; r < N; ++r)
      for (int c = r; c < N; ++c) M(r, c) = M(c, r) = f32(what);
    return M;
  }
};

bool normalizedAngle(double a) { return a > -laser_features::kPi - 1e-12 && a <= laser_features::kPi + 1e-12; }

/// Positive semi-definite within rounding: the smallest eigenvalue is >= -tolerance times the largest
/// magnitude (the eigenvalues of a saved P are >= 0 up to ~1e-15 of its norm; of a float32 one, ~1e-7).
bool positiveSemiDefinite(const Eigen::MatrixXd& M, double tolerance = kPsdToleranceF64) {
  if (M.size() == 0) return true;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(M, Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) return false;
  const double scale = std::max(eigen.eigenvalues().cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  return eigen.eigenvalues().minCoeff() >= -tolerance * scale;
}

std::string placeContext(size_t index, uint32_t id) {
  return "place #" + std::to_string(index) + " (id " + std::to_string(id) + ")";
}

/// What precedes a place's body.
struct PlaceHeader {
  std::string where;  // "place #k (id i)", for messages
  uint32_t version = 0;
  uint32_t flags = 0;
  uint32_t num_lines = 0;
  uint32_t num_doors = 0;
  Pose2D robot;
  bool compact() const { return (flags & kFlagCompact) != 0; }
};

/// Bytes the body after the header needs (checked before allocating anything for the counts).
uint64_t bodyBytes(const PlaceHeader& h) {
  const uint64_t n = h.num_lines, d = h.num_doors;
  if (h.compact()) {
    const uint64_t line = h.version >= 3 ? kCompactLineBytes : kCompactLineBytesV2;
    return kCompactRobotCovBytes + n * line + d * kCompactDoorBytes;
  }
  const uint64_t N = 3 + 2 * n;
  return n * kLineRecordBytes + d * kDoorRecordBytes + N * (N + 1) / 2 * 8;
}

/// The place's id, flags, counts, display pose and robot pose (version 3: after the counts, float32
/// in a compact record; versions 1 and 2: f64, the display pose before the flags); refuses flags the
/// version does not know and counts the rest of the file cannot hold.
bool decodeHeader(Reader* in, size_t index, uint32_t version, Place* place, PlaceHeader* h, std::string* error) {
  place->id = in->u32("a place id");
  h->where = placeContext(index, place->id);
  h->version = version;
  if (version < 3) place->display_pose = in->pose("a place's display pose");
  h->flags = in->u32("a place's flags");
  h->num_lines = in->u32("a place's line count");
  h->num_doors = in->u32("a place's door count");
  if (version < 3) h->robot = in->pose("the robot pose");
  if (!in->ok()) return false;
  const uint32_t known = kFlagRelocationPending | (version >= 2 ? kFlagCompact : 0u);
  if ((h->flags & ~known) != 0) {
    *error = h->where + ": unknown flags " + std::to_string(h->flags) + " for version " + std::to_string(version);
    return false;
  }
  if (version >= 3) {
    place->display_pose = h->compact() ? in->poseF32("a place's display pose") : in->pose("a place's display pose");
    h->robot = h->compact() ? in->poseF32("the robot pose") : in->pose("the robot pose");
    if (!in->ok()) return false;
  }
  if (bodyBytes(*h) > in->remaining()) {
    *error = h->where + ": " + std::to_string(h->num_lines) + " lines and " + std::to_string(h->num_doors) +
             " doors need " + std::to_string(bodyBytes(*h)) + " more bytes, the file has " +
             std::to_string(in->remaining()) + " (truncated?)";
    return false;
  }
  return true;
}

/// Keeps a decoded door; refuses a duplicate id, a heading outside (-pi, pi] or an indefinite covariance.
bool keepDoor(const Door& door, const PlaceHeader& h, double psd_tolerance, Place* place, std::string* error) {
  if (!place->doors.emplace(door.id, door).second) {
    *error = h.where + ": door id " + std::to_string(door.id) + " appears twice";
    return false;
  }
  if (!normalizedAngle(door.pose.theta) || !positiveSemiDefinite(door.cov, psd_tolerance)) {
    *error = h.where + ", door " + std::to_string(door.id) +
             ": angle not in (-pi, pi] or covariance not positive semi-definite";
    return false;
  }
  return true;
}

/// The full record: f64 lines with extents, doors, the joint covariance P (versions 1 and 2).
bool decodeFullBody(Reader* in, const PlaceHeader& h, Place* place, std::vector<MapLine>* lines,
                    Eigen::MatrixXd* P, std::string* error) {
  lines->resize(h.num_lines);
  for (MapLine& line : *lines) {
    line.line.alpha = in->f64("a line");
    line.line.r = in->f64("a line");
    line.extent_start.x() = in->f64("a line extent");
    line.extent_start.y() = in->f64("a line extent");
    line.extent_end.x() = in->f64("a line extent");
    line.extent_end.y() = in->f64("a line extent");
  }
  for (uint32_t d = 0; d < h.num_doors; ++d) {
    Door door;
    door.id = in->u32("a door id");
    door.pose = in->pose("a door pose");
    for (int r = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c) door.cov(r, c) = door.cov(c, r) = in->f64("a door covariance");
    if (!in->ok() || !keepDoor(door, h, kPsdToleranceF64, place, error)) return false;
  }
  const Eigen::Index n = Eigen::Index(3 + 2 * size_t(h.num_lines));
  P->resize(n, n);
  for (Eigen::Index r = 0; r < n; ++r)
    for (Eigen::Index c = 0; c <= r; ++c) (*P)(r, c) = (*P)(c, r) = in->f64("the covariance");
  if (!in->ok()) return false;
  if ((P->diagonal().array() < 0.0).any() || !positiveSemiDefinite(*P)) {
    *error = h.where + ": the covariance (" + std::to_string(n) + "x" + std::to_string(n) +
             ") is not positive semi-definite";
    return false;
  }
  return true;
}

/// A compact line's extent: version 3 stores its end points as positions along the line and rebuilds
/// them on the line just read (alpha, r); version 2 stores the points themselves.
void decodeCompactExtent(Reader* in, uint32_t version, MapLine* line) {
  if (version >= 3) {
    const double start = in->f32("a line extent");
    const double end = in->f32("a line extent");
    line->extent_start = pointOnLine(line->line, start);
    line->extent_end = pointOnLine(line->line, end);
    return;
  }
  line->extent_start.x() = in->f32("a line extent");
  line->extent_start.y() = in->f32("a line extent");
  line->extent_end.x() = in->f32("a line extent");
  line->extent_end.y() = in->f32("a line extent");
}

/// The compact record (versions 2 and 3): float32 lines with extents and marginals, the robot's
/// marginal, doors (the poses are read with the header). P is rebuilt BLOCK-DIAGONAL from the
/// marginals. Why that is enough: after a load no place is active; entering one, relocation
/// (PlaceMaps::relocateAtDoor -> StochasticMap::relocate) replaces the robot's pose and covariance
/// and zeroes the robot-line cross-covariances, and the update that judges it (joint NIS, eqs.
/// 13-14) and fuses it (eqs. 15-17) uses P's line blocks and line-line cross-covariances. With
/// these zero, each line keeps its exact marginal and the lines count as independent; the robot's
/// block is its marginal, uncorrelated with the lines, as relocate() leaves it.
bool decodeCompactBody(Reader* in, const PlaceHeader& h, Place* place, std::vector<MapLine>* lines,
                       Eigen::MatrixXd* P, std::string* error) {
  const Eigen::Index n = Eigen::Index(3 + 2 * size_t(h.num_lines));
  *P = Eigen::MatrixXd::Zero(n, n);
  P->topLeftCorner<3, 3>() = in->symmetricF32<3>("the robot covariance");
  if (in->ok() && !positiveSemiDefinite(P->topLeftCorner<3, 3>(), kPsdToleranceF32)) {
    *error = h.where + ": the robot covariance is not positive semi-definite";
    return false;
  }
  lines->resize(h.num_lines);
  for (size_t i = 0; i < lines->size() && in->ok(); ++i) {
    MapLine& line = (*lines)[i];
    line.line.alpha = in->f32("a line");
    line.line.r = in->f32("a line");
    decodeCompactExtent(in, h.version, &line);
    const Eigen::Matrix2d marginal = in->symmetricF32<2>("a line covariance");
    if (in->ok() && !positiveSemiDefinite(marginal, kPsdToleranceF32)) {
      *error = h.where + ", line " + std::to_string(i) + ": the covariance is not positive semi-definite";
      return false;
    }
    P->block<2, 2>(Eigen::Index(3 + 2 * i), Eigen::Index(3 + 2 * i)) = marginal;
  }
  for (uint32_t d = 0; d < h.num_doors && in->ok(); ++d) {
    Door door;
    door.id = in->u32("a door id");
    door.pose = in->poseF32("a door pose");
    door.cov = in->symmetricF32<3>("a door covariance");
    if (in->ok() && !keepDoor(door, h, kPsdToleranceF32, place, error)) return false;
  }
  return in->ok();
}

/// Reads one place record; returns false with the reader's or `error`'s message.
bool decodePlace(Reader* in, size_t index, uint32_t version, const StochasticMapParams& params, Place* place,
                 std::string* error) {
  PlaceHeader h;
  if (!decodeHeader(in, index, version, place, &h, error)) return false;
  std::vector<MapLine> lines;
  Eigen::MatrixXd P;
  const bool body = h.compact() ? decodeCompactBody(in, h, place, &lines, &P, error)
                                : decodeFullBody(in, h, place, &lines, &P, error);
  if (!body) return false;
  if (!normalizedAngle(h.robot.theta)) {
    *error = h.where + ": robot heading " + std::to_string(h.robot.theta) + " not in (-pi, pi]";
    return false;
  }
  for (size_t i = 0; i < lines.size(); ++i) {
    if (!normalizedAngle(lines[i].line.alpha) || lines[i].line.r < 0.0) {
      *error = h.where + ", line " + std::to_string(i) + ": (alpha, r) = (" + std::to_string(lines[i].line.alpha) +
               ", " + std::to_string(lines[i].line.r) + ") is not canonical (alpha in (-pi, pi], r >= 0)";
      return false;
    }
  }
  place->map = StochasticMap(params);
  place->map.setState(h.robot, lines, P, (h.flags & kFlagRelocationPending) != 0);
  return true;
}

IoResult failure(const std::string& name, const std::string& what) {
  return {false, "cannot load places from '" + name + "': " + what};
}

}  // namespace

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
  if (version < kPlacesOldestFormatVersion) {
    // Version 1 is the first format; an older number was never written by hybrid_slam.
    return failure(name, "format version " + std::to_string(version) + " is older than this build reads (" +
                             std::to_string(kPlacesOldestFormatVersion) + ".." + std::to_string(kPlacesFormatVersion) +
                             ") and has no migration; build the map again");
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
    if (!decodePlace(&in, k, uint32_t(version), maps->params(), &place, &error)) break;
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

IoResult loadPlaces(const std::string& path, PlaceMaps* maps) {
  std::string bytes, error;
  if (!laser_features::readWholeFile(path, &bytes, &error)) return failure(path, error);
  return decodePlaces(bytes, path, maps);
}

}  // namespace ekf_local_map
