#include "exploration/occupancy_grid.h"

#include "core_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace exploration {

using laser_features::kTwoPi;
using laser_features::Pose2D;

namespace {

constexpr std::int8_t kNever = std::numeric_limits<std::int8_t>::min();  // never observed
constexpr int kLevels = 127;                // quantization levels on each side of log-odds 0
constexpr double kMaxIndex = 1 << 29;       // |cell index| bound: sums of indices stay in int
constexpr double kSurfaceClearance = 1.2;   // cells: free space stops this far (across) from a surface:
                                            // half a cell's diagonal plus half a cell of Bresenham
constexpr double kTangentSlope = 0.05;      // a return is on another's surface line within this much
                                            // of their distance (on top of breakpoint_margin)

using core::fail;
using core::finite;

double logit(double p) { return std::log(p / (1.0 - p)); }

}  // namespace

const char* toString(CellState state) {
  switch (state) {
    case CellState::Unknown: return "Unknown";
    case CellState::Free: return "Free";
    case CellState::Occupied: return "Occupied";
  }
  return "?";
}

bool OccupancyGrid::validate(const OccupancyGridParams& p, std::string* error) {
  if (!(p.resolution > 0.0) || !std::isfinite(p.resolution)) return fail(error, "resolution must be > 0");
  if (!(p.l_min < 0.0) || !(p.l_max > 0.0) || !std::isfinite(p.l_min) || !std::isfinite(p.l_max))
    return fail(error, "need l_min < 0 < l_max (finite)");
  const double step = std::max(-p.l_min, p.l_max) / kLevels;
  if (!(p.l_occ >= 0.5 * step) || !(p.l_occ <= p.l_max - p.l_min))
    return fail(error, "l_occ must be > 0 (at least half a quantization level) and <= l_max - l_min");
  if (!(p.l_free <= -0.5 * step) || !(p.l_free >= p.l_min - p.l_max))
    return fail(error, "l_free must be < 0 (at least half a quantization level) and >= l_min - l_max");
  if (!(p.free_threshold > 0.0) || !(p.occupied_threshold < 1.0) ||
      !(p.free_threshold < p.occupied_threshold))
    return fail(error, "need 0 < free_threshold < occupied_threshold < 1");
  if (!(logit(p.occupied_threshold) <= p.l_max) || !(logit(p.free_threshold) >= p.l_min))
    return fail(error, "the thresholds must be reachable within [l_min, l_max]");
  if (!(p.max_range > 0.0) || !(p.max_range / p.resolution < kMaxIndex / 4))
    return fail(error, "max_range must be > 0 and finite");
  if (!(p.min_range >= 0.0) || !(p.min_range < p.max_range)) return fail(error, "need 0 <= min_range < max_range");
  if (!(p.no_return_free_range >= 0.0) || !std::isfinite(p.no_return_free_range))
    return fail(error, "no_return_free_range must be >= 0 and finite");
  if (!(p.grow_margin >= 0.0) || !(p.grow_margin / p.resolution < kMaxIndex / 4))
    return fail(error, "grow_margin must be >= 0 and finite");
  if (!(p.breakpoint_lambda > 0.0) || !(p.breakpoint_lambda < 0.5 * laser_features::kPi))
    return fail(error, "breakpoint_lambda must be in (0, pi/2)");
  if (!(p.breakpoint_margin >= 0.0) || !std::isfinite(p.breakpoint_margin))
    return fail(error, "breakpoint_margin must be >= 0");
  if (!(p.max_surface_gap >= 0.0) || !std::isfinite(p.max_surface_gap))
    return fail(error, "max_surface_gap must be >= 0");
  if (p.max_cells == 0) return fail(error, "max_cells must be > 0");
  return true;
}

OccupancyGrid::OccupancyGrid(const OccupancyGridParams& params) : params_(params) {
  std::string why;
  if (!validate(params_, &why)) throw std::invalid_argument("OccupancyGrid: " + why);
  step_ = std::max(-params_.l_min, params_.l_max) / kLevels;
  d_occ_ = static_cast<int>(std::lround(params_.l_occ / step_));
  d_free_ = static_cast<int>(std::lround(params_.l_free / step_));
  v_min_ = static_cast<int>(std::lround(params_.l_min / step_));
  v_max_ = static_cast<int>(std::lround(params_.l_max / step_));
  l_occ_thr_ = logit(params_.occupied_threshold);
  l_free_thr_ = logit(params_.free_threshold);
}

OccupancyGrid::OccupancyGrid(const OccupancyGridParams& params, const GridBounds& b) : OccupancyGrid(params) {
  const double r = params_.resolution;
  if (!std::isfinite(b.min_x) || !std::isfinite(b.min_y) || !std::isfinite(b.max_x) || !std::isfinite(b.max_y) ||
      !(b.max_x > b.min_x) || !(b.max_y > b.min_y) || std::abs(b.min_x) / r > kMaxIndex ||
      std::abs(b.max_x) / r > kMaxIndex || std::abs(b.min_y) / r > kMaxIndex || std::abs(b.max_y) / r > kMaxIndex)
    throw std::invalid_argument("OccupancyGrid: bounds must be finite and non-empty");
  const int x0 = static_cast<int>(std::floor(b.min_x / r)), y0 = static_cast<int>(std::floor(b.min_y / r));
  const int x1 = static_cast<int>(std::ceil(b.max_x / r)), y1 = static_cast<int>(std::ceil(b.max_y / r));
  const double cells = static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0);
  if (cells > static_cast<double>(params_.max_cells))
    throw std::invalid_argument("OccupancyGrid: bounds need more than max_cells cells");
  min_x_ = x0;
  min_y_ = y0;
  width_ = x1 - x0;
  height_ = y1 - y0;
  cells_.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), kNever);
  fixed_ = true;
}

// ---------------------------------------------------------------------------------------------
// Queries

CellState OccupancyGrid::classify(std::int8_t v) const {
  if (v == kNever) return CellState::Unknown;
  const double l = v * step_;
  if (l >= l_occ_thr_) return CellState::Occupied;
  if (l <= l_free_thr_) return CellState::Free;
  return CellState::Unknown;  // conflicting evidence
}

CellState OccupancyGrid::cellState(int ix, int iy) const {
  return contains(ix, iy) ? classify(cells_[index(ix, iy)]) : CellState::Unknown;
}

double OccupancyGrid::probability(int ix, int iy) const {
  if (!contains(ix, iy)) return 0.5;
  const std::int8_t v = cells_[index(ix, iy)];
  if (v == kNever) return 0.5;
  return 1.0 / (1.0 + std::exp(-v * step_));
}

bool OccupancyGrid::observed(int ix, int iy) const { return contains(ix, iy) && cells_[index(ix, iy)] != kNever; }

CellIndex OccupancyGrid::worldToCell(const Eigen::Vector2d& p) const {
  // Non-finite or absurd coordinates land far outside any grid (contains() is false).
  const auto to_index = [this](double v) {
    const double f = std::floor(v / params_.resolution);
    if (!(std::abs(f) <= 2 * kMaxIndex)) return std::numeric_limits<int>::min() / 2;
    return static_cast<int>(f);
  };
  return {to_index(p.x()), to_index(p.y())};
}

Eigen::Vector2d OccupancyGrid::cellCenter(int ix, int iy) const {
  return {(ix + 0.5) * params_.resolution, (iy + 0.5) * params_.resolution};
}

std::size_t OccupancyGrid::count(CellState state) const {
  std::size_t n = 0;
  for (const std::int8_t v : cells_) n += classify(v) == state ? 1 : 0;
  return n;
}

void OccupancyGrid::toOccupancyData(std::vector<std::int8_t>* data) const {
  data->resize(cells_.size());
  for (std::size_t i = 0; i < cells_.size(); ++i) {
    const std::int8_t v = cells_[i];
    (*data)[i] = v == kNever ? std::int8_t{-1}
                             : static_cast<std::int8_t>(std::lround(100.0 / (1.0 + std::exp(-v * step_))));
  }
}

// ---------------------------------------------------------------------------------------------
// Updates

bool OccupancyGrid::ensureCovers(int x0, int y0, int x1, int y1, std::string* error) {
  if (fixed_) return true;  // clipped cell by cell
  if (!cells_.empty() && contains(x0, y0) && contains(x1, y1)) return true;
  const int m = static_cast<int>(std::ceil(params_.grow_margin / params_.resolution));
  int nx0 = x0 - m, ny0 = y0 - m, nx1 = x1 + m, ny1 = y1 + m;  // inclusive
  if (!cells_.empty()) {
    // Keep the old extent; grow only the sides that need it.
    nx0 = x0 < min_x_ ? nx0 : min_x_;
    ny0 = y0 < min_y_ ? ny0 : min_y_;
    nx1 = x1 >= min_x_ + width_ ? nx1 : min_x_ + width_ - 1;
    ny1 = y1 >= min_y_ + height_ ? ny1 : min_y_ + height_ - 1;
  }
  const double cells = (static_cast<double>(nx1) - nx0 + 1) * (static_cast<double>(ny1) - ny0 + 1);
  if (cells > static_cast<double>(params_.max_cells)) return fail(error, "the grid would exceed max_cells");
  const int w = nx1 - nx0 + 1, h = ny1 - ny0 + 1;
  std::vector<std::int8_t> grown(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), kNever);
  for (int y = 0; y < height_; ++y) {
    const auto src = cells_.begin() + static_cast<std::ptrdiff_t>(y) * width_;
    const std::size_t dst = static_cast<std::size_t>(y + min_y_ - ny0) * w + static_cast<std::size_t>(min_x_ - nx0);
    std::copy(src, src + width_, grown.begin() + static_cast<std::ptrdiff_t>(dst));
  }
  cells_.swap(grown);
  min_x_ = nx0;
  min_y_ = ny0;
  width_ = w;
  height_ = h;
  return true;
}

template <typename Visit>
void OccupancyGrid::bresenham(const CellIndex& from, const CellIndex& to, Visit visit) {
  int x = from.x, y = from.y;
  const int dx = std::abs(to.x - x), dy = -std::abs(to.y - y);
  const int sx = x < to.x ? 1 : -1, sy = y < to.y ? 1 : -1;
  int err = dx + dy;
  while (true) {
    const bool end = x == to.x && y == to.y;
    visit(x, y, end);
    if (end) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
}

void OccupancyGrid::traceFree(const CellIndex& from, const CellIndex& to, bool include_end) {
  bresenham(from, to, [&](int x, int y, bool end) {
    if ((include_end || !end) && contains(x, y)) misses_.push_back(index(x, y));
  });
}

void OccupancyGrid::traceHits(const CellIndex& from, const CellIndex& to) {
  bresenham(from, to, [&](int x, int y, bool) {
    if (contains(x, y)) hits_.push_back(index(x, y));
  });
}

void OccupancyGrid::fillTriangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  // Scanline: per row of cells, the cells whose centres lie in the triangle (edges included, so
  // adjacent triangles leave no gap).
  const double res = params_.resolution, eps = 1e-9;
  const Eigen::Vector2d v[3] = {a, b, c};
  const double y_lo = std::min({a.y(), b.y(), c.y()}), y_hi = std::max({a.y(), b.y(), c.y()});
  const int row0 = static_cast<int>(std::ceil(y_lo / res - 0.5 - eps));
  const int row1 = static_cast<int>(std::floor(y_hi / res - 0.5 + eps));
  for (int iy = row0; iy <= row1; ++iy) {
    const double y = (iy + 0.5) * res;
    double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& p = v[k];
      const Eigen::Vector2d& q = v[(k + 1) % 3];
      if ((y < std::min(p.y(), q.y()) - eps) || (y > std::max(p.y(), q.y()) + eps)) continue;
      if (std::abs(q.y() - p.y()) < eps) {  // a horizontal edge on the row
        x_lo = std::min({x_lo, p.x(), q.x()});
        x_hi = std::max({x_hi, p.x(), q.x()});
        continue;
      }
      const double t = std::clamp((y - p.y()) / (q.y() - p.y()), 0.0, 1.0);
      const double x = p.x() + t * (q.x() - p.x());
      x_lo = std::min(x_lo, x);
      x_hi = std::max(x_hi, x);
    }
    if (!(x_lo <= x_hi)) continue;
    const int col0 = static_cast<int>(std::ceil(x_lo / res - 0.5 - eps));
    const int col1 = static_cast<int>(std::floor(x_hi / res - 0.5 + eps));
    for (int ix = col0; ix <= col1; ++ix)
      if (contains(ix, iy)) misses_.push_back(index(ix, iy));
  }
}

void OccupancyGrid::applyUpdates() {
  // Each cell the scan touched is updated once: as a hit if any beam ended in it (a return of this
  // scan wins over the beams that crossed it), else as free. A bit per cell for this scan alone
  // finds the duplicates in linear time (sorting the touched cells took a quarter of the
  // coordinator's time); it is not part of the map's memory.
  std::vector<bool> touched(cells_.size(), false);
  const auto update = [this, &touched](std::size_t i, int delta) {
    if (touched[i]) return;
    touched[i] = true;
    const int v = cells_[i] == kNever ? 0 : cells_[i];
    cells_[i] = static_cast<std::int8_t>(std::clamp(v + delta, v_min_, v_max_));
  };
  for (const std::size_t i : hits_) update(i, d_occ_);
  for (const std::size_t i : misses_) update(i, d_free_);
  hits_.clear();
  misses_.clear();
}

bool OccupancyGrid::insertScan(const Pose2D& sensor_in_map, const std::vector<float>& ranges, double angle_min,
                               double angle_increment, std::string* error) {
  return insert(sensor_in_map, ranges, angle_min, angle_increment, error);
}

bool OccupancyGrid::insertScan(const Pose2D& sensor_in_map, const std::vector<double>& ranges, double angle_min,
                               double angle_increment, std::string* error) {
  return insert(sensor_in_map, ranges, angle_min, angle_increment, error);
}

template <typename T>
bool OccupancyGrid::insert(const Pose2D& pose, const std::vector<T>& ranges, double angle_min,
                           double angle_increment, std::string* error) {
  if (!finite(pose)) return fail(error, "non-finite sensor pose");
  if (!std::isfinite(angle_min) || !std::isfinite(angle_increment)) return fail(error, "non-finite scan angles");
  const double res = params_.resolution;
  if (std::abs(pose.x) / res > kMaxIndex || std::abs(pose.y) / res > kMaxIndex)
    return fail(error, "sensor pose too far from the origin");

  // The beams in the map frame, and the extent they need (a growing grid reallocates once per
  // scan at most).
  const std::size_t n = ranges.size();
  rays_.resize(n);
  const Eigen::Vector2d sensor = pose.translation();
  const CellIndex origin = worldToCell(sensor);
  int x0 = origin.x, y0 = origin.y, x1 = origin.x, y1 = origin.y;
  std::size_t valid = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Ray& ray = rays_[i];
    ray = Ray();
    const double r = static_cast<double>(ranges[i]);
    if (std::isnan(r) || r <= params_.min_range) continue;  // also -inf
    if (std::isinf(r)) {
      ray.length = std::min(params_.no_return_free_range, params_.max_range);
    } else if (r >= params_.max_range) {
      ray.length = params_.max_range;
    } else {
      ray.length = r;
      ray.hit = true;
    }
    if (!(ray.length > 0.0)) continue;
    ray.valid = true;
    ++valid;
    const double bearing = angle_min + static_cast<double>(i) * angle_increment;
    ray.dir = laser_features::unitVector(pose.theta + bearing);
    ray.end = laser_features::transformPoint(pose, ray.length * laser_features::unitVector(bearing));
    ray.cell = worldToCell(ray.end);
    x0 = std::min(x0, ray.cell.x);
    y0 = std::min(y0, ray.cell.y);
    x1 = std::max(x1, ray.cell.x);
    y1 = std::max(y1, ray.cell.y);
  }
  if (valid == 0) {  // nothing to write (not even the sensor's cell)
    ++scans_;
    return true;
  }
  if (!ensureCovers(x0 - 1, y0 - 1, x1 + 1, y1 + 1, error)) return false;

  // A full turn: the last beam is adjacent to the first.
  BeamOrder order;
  order.n = n;
  order.wraps = n > 2 && std::abs(std::abs(angle_increment) * static_cast<double>(n) - kTwoPi) <
                             0.5 * std::abs(angle_increment);
  joinSurfaces(order, angle_increment);
  surfaceTangents(order);
  traceBeams(order, sensor, origin);
  if (params_.fill_gaps) fillWedges(order, sensor);
  applyUpdates();
  ++scans_;
  return true;
}

void OccupancyGrid::joinSurfaces(const BeamOrder& order, double angle_increment) {
  // Adjacent returns on one surface: the adaptive breakpoint test (Borges & Aldon 2004, as the line
  // extractor of laser_features segments scans), or, for a surface seen too grazing for it, the
  // two returns in line with a third adjacent one; never farther apart than max_surface_gap.
  const std::size_t n = order.n;
  const double dphi = std::abs(angle_increment), lambda = params_.breakpoint_lambda;
  const double break_ratio = lambda > dphi ? std::sin(dphi) / std::sin(lambda - dphi) : -1.0;
  const double max_gap = params_.max_surface_gap, margin = params_.breakpoint_margin;
  const auto inLine = [&](const Ray& a, const Ray& b, std::size_t k, const Ray& near) {
    if (k >= n || !rays_[k].valid || !rays_[k].hit) return false;
    const Eigen::Vector2d& p = rays_[k].end;
    const Eigen::Vector2d ab = b.end - a.end;
    return (p - near.end).norm() <= max_gap && std::abs(laser_features::cross2(ab, p - a.end)) <= margin * ab.norm();
  };
  joined_.assign(n, 0);  // joined_[i]: beams i and next(i) are one surface
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = order.next(i);
    if (j >= n) continue;
    const Ray& a = rays_[i];
    const Ray& b = rays_[j];
    if (!a.valid || !b.valid || !a.hit || !b.hit) continue;
    if ((b.end - a.end).norm() > max_gap) continue;  // bounds a false chord across a depth step
    const double jump = std::abs(a.length - b.length);
    const bool breakpoint_ok = break_ratio >= 0.0 && jump <= std::min(a.length, b.length) * break_ratio + margin;
    joined_[i] = breakpoint_ok || inLine(a, b, order.prev(i), a) || inLine(a, b, order.next(j), b) ? 1 : 0;
  }
}

void OccupancyGrid::surfaceTangents(const BeamOrder& order) {
  // The surface's direction at each return, from the chords to the returns it is joined with; for
  // a return joined to none, the line through its neighbours' returns when it lies on it (a wall
  // seen so grazing that its returns are far apart: the direction only stops free space short of
  // the wall, it joins nothing).
  const std::size_t n = order.n;
  const double margin = params_.breakpoint_margin;
  for (std::size_t i = 0; i < n; ++i) {
    Ray& ray = rays_[i];
    if (!ray.hit) continue;
    Eigen::Vector2d t = Eigen::Vector2d::Zero();
    const std::size_t before = order.prev(i), after = order.next(i);
    if (before < n && joined_[before]) t += (ray.end - rays_[before].end).normalized();
    if (after < n && joined_[i]) t += (rays_[after].end - ray.end).normalized();
    if (t.squaredNorm() == 0.0 && before < n && after < n && rays_[before].hit && rays_[after].hit) {
      const Eigen::Vector2d chord = rays_[after].end - rays_[before].end;
      const double len = chord.norm();
      if (len > 1e-9 && std::abs(laser_features::cross2(chord, ray.end - rays_[before].end)) <= margin * len &&
          chord.dot(ray.end - rays_[before].end) > 0.0 && chord.dot(rays_[after].end - ray.end) > 0.0)
        t = chord;
    }
    ray.tangent = t.norm() > 1e-9 ? Eigen::Vector2d(t.normalized()) : Eigen::Vector2d::Zero();
  }
}

Eigen::Vector2d OccupancyGrid::sharedTangent(const Ray& a, const Ray& b) const {
  const double margin = params_.breakpoint_margin;
  const auto passes = [&](const Ray& s, const Ray& o) {
    const double d = (o.end - s.end).norm();
    return s.tangent.squaredNorm() > 0.0 &&
           std::abs(laser_features::cross2(s.tangent, o.end - s.end)) <= margin + kTangentSlope * d;
  };
  if (passes(a, b)) return a.tangent;
  if (passes(b, a)) return b.tangent;
  return Eigen::Vector2d::Zero();
}

double OccupancyGrid::pullback(const Ray& a, const Eigen::Vector2d& t) const {
  const double clearance = kSurfaceClearance * params_.resolution;
  const double sin_grazing = t.squaredNorm() > 0.0 ? std::abs(laser_features::cross2(a.dir, t)) : 1.0;
  return sin_grazing * a.length > clearance ? clearance / sin_grazing : a.length;
}

void OccupancyGrid::traceBeams(const BeamOrder& order, const Eigen::Vector2d& sensor, const CellIndex& origin) {
  const std::size_t n = order.n;
  for (std::size_t i = 0; i < n; ++i) {
    const Ray& ray = rays_[i];
    if (!ray.valid) continue;
    if (!ray.hit) {
      traceFree(origin, ray.cell, true);
      continue;
    }
    if (contains(ray.cell.x, ray.cell.y)) hits_.push_back(index(ray.cell.x, ray.cell.y));
    // A nearer neighbour not joined but on the same surface (a wall seen grazing): the beam skims
    // that surface before its return, stop short of it (else it erases the wall).
    double stop = 0.0;
    const std::size_t before = order.prev(i), after = order.next(i);
    for (const std::size_t k : {before, after}) {
      if (k >= n || (k == before ? joined_[before] : joined_[i])) continue;
      const Ray& other = rays_[k];
      if (!other.valid || !other.hit || other.length >= ray.length) continue;
      const Eigen::Vector2d t = sharedTangent(other, ray);
      if (t.squaredNorm() > 0.0) stop = std::max(stop, pullback(ray, t));
    }
    if (stop <= 0.0) {
      traceFree(origin, ray.cell, false);
    } else {
      const CellIndex c = worldToCell(sensor + std::max(ray.length - stop, 0.0) * ray.dir);
      traceFree(origin, c, c != ray.cell);
    }
  }
}

void OccupancyGrid::fillWedges(const BeamOrder& order, const Eigen::Vector2d& sensor) {
  const std::size_t n = order.n;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = order.next(i);
    if (j >= n || !rays_[i].valid || !rays_[j].valid) continue;
    const Ray& a = rays_[i];
    const Ray& b = rays_[j];
    if (joined_[i]) {
      // One surface: free up to it, and the surface between the returns is occupied.
      fillTriangle(sensor, a.end, b.end);
      traceHits(a.cell, b.cell);
      continue;
    }
    const Eigen::Vector2d t = a.hit && b.hit ? sharedTangent(a, b) : Eigen::Vector2d::Zero();
    if (t.squaredNorm() > 0.0) {
      // One surface not joined: free up to a cell and a bit short of it.
      const double ra = a.length - pullback(a, t), rb = b.length - pullback(b, t);
      if (ra > 0.0 || rb > 0.0)
        fillTriangle(sensor, sensor + std::max(ra, 0.0) * a.dir, sensor + std::max(rb, 0.0) * b.dir);
      continue;
    }
    // A break: free up to the nearer return, short of its surface (which ends between the beams).
    const Ray& nearer = a.length <= b.length ? a : b;
    const double reach = nearer.hit ? nearer.length - pullback(nearer, nearer.tangent) : nearer.length;
    if (reach > 0.0) fillTriangle(sensor, sensor + reach * a.dir, sensor + reach * b.dir);
  }
}

// ---------------------------------------------------------------------------------------------

bool OccupancyGrid::setCell(int ix, int iy, CellState state) {
  if (std::abs(static_cast<double>(ix)) > kMaxIndex || std::abs(static_cast<double>(iy)) > kMaxIndex) return false;
  if (!ensureCovers(ix, iy, ix, iy, nullptr) || !contains(ix, iy)) return false;
  std::int8_t& v = cells_[index(ix, iy)];
  switch (state) {
    case CellState::Unknown: v = kNever; break;
    case CellState::Free: v = static_cast<std::int8_t>(v_min_); break;
    case CellState::Occupied: v = static_cast<std::int8_t>(v_max_); break;
  }
  return true;
}

}  // namespace exploration
