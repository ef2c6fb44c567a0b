#include "exploration/grid_planner.h"

#include "core_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <queue>
#include <stdexcept>

namespace exploration {

namespace {

using core::fail;
using core::finite;

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr float kInf = std::numeric_limits<float>::infinity();

using core::kDx;
using core::kDy;

}  // namespace

bool GridPlanner::validate(const PlannerParams& p, std::string* error) {
  if (!(p.robot_radius >= 0.0) || !std::isfinite(p.robot_radius)) return fail(error, "robot_radius must be >= 0");
  if (!(p.safety_margin >= 0.0) || !std::isfinite(p.safety_margin)) return fail(error, "safety_margin must be >= 0");
  if (!(p.start_escape_distance >= 0.0) || !std::isfinite(p.start_escape_distance))
    return fail(error, "start_escape_distance must be >= 0");
  if (!(p.max_segment_length >= 0.0) || !std::isfinite(p.max_segment_length))
    return fail(error, "max_segment_length must be >= 0 (0: no limit)");
  return true;
}

GridPlanner::GridPlanner(const PlannerParams& params) : params_(params) {
  std::string why;
  if (!validate(params_, &why)) throw std::invalid_argument("GridPlanner: " + why);
}

void GridPlanner::setMap(const OccupancyGrid& grid) {
  resolution_ = grid.resolution();
  min_x_ = grid.minX();
  min_y_ = grid.minY();
  width_ = grid.width();
  height_ = grid.height();
  const std::size_t n = grid.cellCount();
  distances_valid_ = false;
  start_ = -1;
  seen_.clear();
  seen_first_.clear();
  seen_near_.clear();

  std::vector<CellState> state(n);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      state[static_cast<std::size_t>(y) * width_ + x] = grid.cellState(min_x_ + x, min_y_ + y);
  pass_.assign(n, kBlocked);
  for (std::size_t i = 0; i < n; ++i)
    if (state[i] == CellState::Free || (state[i] == CellState::Unknown && params_.allow_unknown)) pass_[i] = kOpen;

  // The inflation disk, stamped around the Occupied cells on an obstacle's boundary (the nearest
  // obstacle cell to any outside cell is on the boundary), and around the Unknown cells next to Free
  // ones (with inflate_unknown).
  const double r = inflationRadius() / resolution_;
  const int rc = static_cast<int>(std::floor(r));
  std::vector<std::pair<int, int>> disk;
  for (int dy = -rc; dy <= rc; ++dy)
    for (int dx = -rc; dx <= rc; ++dx)
      if (dx * dx + dy * dy <= r * r + 1e-9) disk.emplace_back(dx, dy);
  const bool unknown_blocks = params_.inflate_unknown && !params_.allow_unknown;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      const CellState s = state[static_cast<std::size_t>(y) * width_ + x];
      if (s == CellState::Free || (s == CellState::Unknown && !unknown_blocks)) continue;
      bool source = false;
      for (int k = 0; k < 8 && !source; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) {
          source = s == CellState::Occupied;
          continue;
        }
        const CellState o = state[static_cast<std::size_t>(ny) * width_ + nx];
        source = s == CellState::Occupied ? o != CellState::Occupied : o == CellState::Free;
      }
      if (!source) continue;
      for (const auto& [dx, dy] : disk) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        std::uint8_t& p = pass_[static_cast<std::size_t>(ny) * width_ + nx];
        if (p == kOpen) p = kInflated;
      }
    }
  }
}

void GridPlanner::addObstacles(const std::vector<Eigen::Vector2d>& points) {
  if (!hasMap()) return;
  for (const Eigen::Vector2d& p : points) {
    int index = 0;
    if (cellOf(p, &index)) seen_.push_back(p);
  }
  if (seen_.empty()) return;
  distances_valid_ = false;
  // A cell is covered by a point when its centre lies within the inflation radius of the point
  // itself (not of the point's cell: the controller measures its clearance from the point).
  const double r2 = inflationRadius() * inflationRadius();
  const int rc = static_cast<int>(std::ceil(inflationRadius() / resolution_)) + 1;
  // Visits every (cell, point) pair of a point's inflation disk.
  const auto forCovered = [&](const auto& visit) {
    for (std::size_t k = 0; k < seen_.size(); ++k) {
      int index = 0;
      cellOf(seen_[k], &index);
      const int x = index % width_, y = index / width_;
      for (int dy = -rc; dy <= rc; ++dy)
        for (int dx = -rc; dx <= rc; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
          const int cell = ny * width_ + nx;
          if ((center(cell) - seen_[k]).squaredNorm() <= r2) visit(cell, static_cast<std::int32_t>(k));
        }
    }
  };
  // Which points cover each cell (two passes: counts, then the indices).
  seen_first_.assign(pass_.size() + 1, 0);
  forCovered([&](int cell, std::int32_t) { ++seen_first_[static_cast<std::size_t>(cell) + 1]; });
  for (std::size_t i = 1; i < seen_first_.size(); ++i) seen_first_[i] += seen_first_[i - 1];
  seen_near_.assign(static_cast<std::size_t>(seen_first_.back()), 0);
  std::vector<std::int32_t> fill(seen_first_.begin(), seen_first_.end() - 1);
  forCovered([&](int cell, std::int32_t k) { seen_near_[static_cast<std::size_t>(fill[cell]++)] = k; });
  for (std::size_t i = 0; i < pass_.size(); ++i)
    if (seen_first_[i + 1] > seen_first_[i] && pass_[i] != kBlocked) pass_[i] = kNearSeen;
  for (const Eigen::Vector2d& p : seen_) {
    int index = 0;
    cellOf(p, &index);
    pass_[static_cast<std::size_t>(index)] = kBlocked;
  }
}

bool GridPlanner::recedes(int from, int to) const {
  if (seen_first_.empty()) return true;
  const Eigen::Vector2d a = center(from), b = center(to);
  for (std::int32_t j = seen_first_[to]; j < seen_first_[to + 1]; ++j) {
    const Eigen::Vector2d& p = seen_[static_cast<std::size_t>(seen_near_[j])];
    if ((b - p).squaredNorm() < (a - p).squaredNorm() - 1e-12) return false;
  }
  return true;
}

bool GridPlanner::traversable(int ix, int iy) const {
  const int x = ix - min_x_, y = iy - min_y_;
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
  return pass_[static_cast<std::size_t>(y) * width_ + x] == kOpen;
}

bool GridPlanner::clearLine(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  int ca = 0, cb = 0;
  return cellOf(a, &ca) && cellOf(b, &cb) && lineOfSight(ca, cb);
}

bool GridPlanner::cellOf(const Eigen::Vector2d& p, int* index) const {
  if (!finite(p) || !hasMap()) return false;
  const double fx = std::floor(p.x() / resolution_) - min_x_, fy = std::floor(p.y() / resolution_) - min_y_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < width_ && fy < height_)) return false;
  *index = static_cast<int>(fy) * width_ + static_cast<int>(fx);
  return true;
}

Eigen::Vector2d GridPlanner::center(int index) const {
  const int x = index % width_, y = index / width_;
  return {(min_x_ + x + 0.5) * resolution_, (min_y_ + y + 0.5) * resolution_};
}

bool GridPlanner::search(int start, int goal) {
  const std::size_t n = pass_.size();
  g_.assign(n, kInf);
  parent_.assign(n, -1);
  start_ = start;
  expanded_ = 0;
  const int gx = goal >= 0 ? goal % width_ : 0, gy = goal >= 0 ? goal / width_ : 0;
  // Octile distance: admissible and consistent for 8-connected moves.
  const auto heuristic = [&](int i) -> float {
    if (goal < 0) return 0.0f;
    const int dx = std::abs(i % width_ - gx), dy = std::abs(i / width_ - gy);
    return static_cast<float>(resolution_ * (std::max(dx, dy) + (kSqrt2 - 1.0) * std::min(dx, dy)));
  };
  const float escape = static_cast<float>(params_.start_escape_distance);
  // A move into a cell: traversable, or (only while still leaving the inflation around the start)
  // a free inflated cell within start_escape_distance, nearer to no seen point it is within the
  // inflation of.
  const auto allowed = [&](int from, int to, float g) {
    const std::uint8_t p = pass_[to];
    if (p == kOpen) return true;
    if (pass_[from] == kOpen || g > escape) return false;
    return p == kInflated || (p == kNearSeen && recedes(from, to));
  };

  struct Entry {
    float f, g;
    int i;
    bool operator>(const Entry& o) const { return f > o.f; }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  g_[start] = 0.0f;
  open.push({heuristic(start), 0.0f, start});
  const float step[2] = {static_cast<float>(resolution_), static_cast<float>(resolution_ * kSqrt2)};
  while (!open.empty()) {
    const Entry e = open.top();
    open.pop();
    if (e.g > g_[e.i]) continue;  // stale
    ++expanded_;
    if (e.i == goal) return true;
    const int x = e.i % width_, y = e.i / width_;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
      const int ni = ny * width_ + nx;
      const float g = e.g + step[k >= 4];
      if (!(g < g_[ni]) || !allowed(e.i, ni, g)) continue;
      // No corner cutting: both orthogonal cells of a diagonal move must be allowed.
      if (k >= 4 && (!allowed(e.i, y * width_ + nx, e.g + step[0]) || !allowed(e.i, ny * width_ + x, e.g + step[0])))
        continue;
      g_[ni] = g;
      parent_[ni] = e.i;
      open.push({g + heuristic(ni), g, ni});
    }
  }
  return goal < 0;
}

bool GridPlanner::lineOfSight(int a, int b) const {
  // Every cell the segment between the two centres touches (a supercover line: through a corner,
  // both cells beside it).
  int x = a % width_, y = a / width_;
  const int x1 = b % width_, y1 = b / width_;
  const int nx = std::abs(x1 - x), ny = std::abs(y1 - y);
  const int sx = x1 > x ? 1 : -1, sy = y1 > y ? 1 : -1;
  const auto open = [this](int cx, int cy) { return pass_[static_cast<std::size_t>(cy) * width_ + cx] == kOpen; };
  if (!open(x, y)) return false;
  for (int ix = 0, iy = 0; ix < nx || iy < ny;) {
    const long long cx = static_cast<long long>(1 + 2 * ix) * ny, cy = static_cast<long long>(1 + 2 * iy) * nx;
    if (cx == cy) {
      if (!open(x + sx, y) || !open(x, y + sy)) return false;
      x += sx;
      y += sy;
      ++ix;
      ++iy;
    } else if (cx < cy) {
      x += sx;
      ++ix;
    } else {
      y += sy;
      ++iy;
    }
    if (!open(x, y)) return false;
  }
  return true;
}

std::optional<Path> GridPlanner::extract(int goal, const Eigen::Vector2d& start_point,
                                         const Eigen::Vector2d& goal_point) const {
  if (goal < 0 || !(g_[goal] < kInf)) return std::nullopt;
  std::vector<int> cells;
  for (int c = goal; c >= 0; c = parent_[c]) cells.push_back(c);
  std::reverse(cells.begin(), cells.end());

  Path path;
  path.cells = cells.size();
  path.waypoints.push_back(start_point);
  const std::size_t last = cells.size() - 1;
  // The escape from the inflation around the start (if any) is one leg.
  std::size_t anchor = 0;
  while (anchor < last && pass_[cells[anchor]] != kOpen) ++anchor;
  if (anchor > 0) path.waypoints.push_back(center(cells[anchor]));
  const double max_len = params_.max_segment_length;
  while (anchor < last) {
    std::size_t best = anchor + 1;
    const Eigen::Vector2d from = center(cells[anchor]);
    for (std::size_t j = anchor + 2; j <= last; ++j) {
      if (max_len > 0.0 && (center(cells[j]) - from).norm() > max_len) break;
      if (!lineOfSight(cells[anchor], cells[j])) break;
      best = j;
    }
    path.waypoints.push_back(center(cells[best]));
    anchor = best;
  }
  if (path.waypoints.size() >= 2) {
    path.waypoints.back() = goal_point;  // in the goal cell
  } else {
    path.waypoints.push_back(goal_point);
  }
  for (std::size_t i = 1; i < path.waypoints.size(); ++i)
    path.length += (path.waypoints[i] - path.waypoints[i - 1]).norm();
  return path;
}

std::optional<Path> GridPlanner::plan(const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  int s = 0, g = 0;
  if (!cellOf(start, &s) || !cellOf(goal, &g)) return std::nullopt;
  distances_valid_ = false;
  if (pass_[g] == kBlocked) return std::nullopt;
  if (!search(s, g)) return std::nullopt;
  return extract(g, start, goal);
}

bool GridPlanner::computeDistances(const Eigen::Vector2d& start) {
  int s = 0;
  distances_valid_ = false;
  if (!cellOf(start, &s)) return false;
  search(s, -1);
  start_point_ = start;
  distances_valid_ = true;
  return true;
}

double GridPlanner::distance(int ix, int iy) const {
  const int x = ix - min_x_, y = iy - min_y_;
  if (!distances_valid_ || x < 0 || y < 0 || x >= width_ || y >= height_)
    return std::numeric_limits<double>::infinity();
  const float g = g_[static_cast<std::size_t>(y) * width_ + x];
  return g < kInf ? static_cast<double>(g) : std::numeric_limits<double>::infinity();
}

std::optional<Path> GridPlanner::pathTo(const Eigen::Vector2d& goal) const {
  int g = 0;
  if (!distances_valid_ || !cellOf(goal, &g)) return std::nullopt;
  return extract(g, start_point_, goal);
}

}  // namespace exploration
