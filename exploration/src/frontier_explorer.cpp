#include "exploration/frontier_explorer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <queue>
#include <stdexcept>

namespace exploration {

namespace {

bool fail(std::string* error, const char* why) {
  if (error) *error = why;
  return false;
}

bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

constexpr double kSqrt2 = 1.41421356237309504880;
constexpr float kInf = std::numeric_limits<float>::infinity();

// The 8 neighbours: the 4 orthogonal ones first.
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};

}  // namespace

// ---------------------------------------------------------------------------------------------
// GridPlanner

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
  // a free inflated cell within start_escape_distance.
  const auto allowed = [&](int from, int to, float g) {
    return pass_[to] == kOpen || (pass_[to] == kInflated && pass_[from] != kOpen && g <= escape);
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

// ---------------------------------------------------------------------------------------------
// Frontiers

std::vector<Frontier> findFrontiers(const OccupancyGrid& grid, double min_size) {
  const int w = grid.width(), h = grid.height(), x0 = grid.minX(), y0 = grid.minY();
  const std::size_t n = grid.cellCount();
  std::vector<CellState> state(n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) state[static_cast<std::size_t>(y) * w + x] = grid.cellState(x0 + x, y0 + y);

  // Open unknown: Unknown cells with no Occupied 8-neighbour. One touching an Occupied cell is the
  // unseen side of that obstacle (a wall's cells between two returns, the row the returns of a wall
  // on a cell boundary round into, conflicting evidence at a face), not space to explore.
  const auto openUnknown = [&](int x, int y) {
    if (state[static_cast<std::size_t>(y) * w + x] != CellState::Unknown) return false;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx >= 0 && ny >= 0 && nx < w && ny < h && state[static_cast<std::size_t>(ny) * w + nx] == CellState::Occupied)
        return false;
    }
    return true;
  };
  // 0: not a frontier cell, 1: a frontier cell not yet clustered, 2: clustered.
  std::vector<std::uint8_t> flag(n, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * w + x;
      if (state[i] != CellState::Free) continue;
      for (int k = 0; k < 4; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;  // the grid's border is no frontier
        if (openUnknown(nx, ny)) {
          flag[i] = 1;
          break;
        }
      }
    }
  }

  std::vector<Frontier> frontiers;
  std::vector<int> stack;
  const double res = grid.resolution();
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (flag[seed] != 1) continue;
    Frontier f;
    flag[seed] = 2;
    stack.assign(1, static_cast<int>(seed));
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    while (!stack.empty()) {
      const int i = stack.back();
      stack.pop_back();
      const int x = i % w, y = i / w;
      f.cells.push_back({x0 + x, y0 + y});
      sum += grid.cellCenter(x0 + x, y0 + y);
      for (int k = 0; k < 8; ++k) {
        const int nx = x + kDx[k], ny = y + kDy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
        const int ni = ny * w + nx;
        if (flag[ni] != 1) continue;
        flag[ni] = 2;
        stack.push_back(ni);
      }
    }
    f.size = static_cast<double>(f.cells.size()) * res;
    if (f.size < min_size - 1e-9) continue;
    f.centroid = sum / static_cast<double>(f.cells.size());
    frontiers.push_back(std::move(f));
  }
  return frontiers;
}

const char* toString(ExplorerStatus status) {
  switch (status) {
    case ExplorerStatus::Goal: return "Goal";
    case ExplorerStatus::Complete: return "Complete";
    case ExplorerStatus::Invalid: return "Invalid";
  }
  return "?";
}

bool FrontierExplorer::validate(const FrontierParams& p, std::string* error) {
  if (!(p.min_frontier_size >= 0.0) || !std::isfinite(p.min_frontier_size))
    return fail(error, "min_frontier_size must be >= 0");
  if (!(p.potential_scale >= 0.0) || !std::isfinite(p.potential_scale))
    return fail(error, "potential_scale must be >= 0");
  if (!(p.gain_scale >= 0.0) || !std::isfinite(p.gain_scale)) return fail(error, "gain_scale must be >= 0");
  if (!(p.goal_search_radius >= 0.0) || !std::isfinite(p.goal_search_radius))
    return fail(error, "goal_search_radius must be >= 0");
  return true;
}

FrontierExplorer::FrontierExplorer(const FrontierParams& params, const PlannerParams& planner_params)
    : params_(params), planner_(planner_params) {
  std::string why;
  if (!validate(params_, &why)) throw std::invalid_argument("FrontierExplorer: " + why);
}

void FrontierExplorer::blacklist(const Eigen::Vector2d& point, double radius) {
  if (!finite(point) || !(radius >= 0.0) || !std::isfinite(radius)) return;
  blacklist_.push_back({point, radius});
}

bool FrontierExplorer::isBlacklisted(const Eigen::Vector2d& p) const {
  for (const Disc& d : blacklist_)
    if ((p - d.center).squaredNorm() <= d.radius * d.radius) return true;
  return false;
}

void FrontierExplorer::chooseGoal(const OccupancyGrid& grid, Frontier* f) {
  // A breadth-first search from the frontier's cells through Free cells (the goal stays on the
  // frontier's side of walls, even unseen ones), up to goal_search_radius: among the reachable
  // traversable cells met, the one nearest the centroid (ties: the shorter path).
  const int w = grid.width(), h = grid.height(), x0 = grid.minX(), y0 = grid.minY();
  if (stamp_.size() != grid.cellCount()) {
    stamp_.assign(grid.cellCount(), 0);
    stamp_counter_ = 0;
  }
  if (++stamp_counter_ == 0) {  // wrapped: start over
    std::fill(stamp_.begin(), stamp_.end(), 0);
    stamp_counter_ = 1;
  }
  const int max_steps = static_cast<int>(std::ceil(params_.goal_search_radius / grid.resolution()));
  queue_.clear();
  for (const CellIndex& c : f->cells) {
    const int i = (c.y - y0) * w + (c.x - x0);
    stamp_[i] = stamp_counter_;
    queue_.emplace_back(i, 0);
  }
  double best_d2 = std::numeric_limits<double>::infinity(), best_path = best_d2;
  for (std::size_t head = 0; head < queue_.size(); ++head) {
    const auto [i, steps] = queue_[head];
    const int x = i % w, y = i / w;
    const double path = planner_.distance(x0 + x, y0 + y);
    // Reachable and traversable (not a cell of the start's escape from the inflation).
    if (path < std::numeric_limits<double>::infinity() && planner_.traversable(x0 + x, y0 + y)) {
      const double d2 = (grid.cellCenter(x0 + x, y0 + y) - f->centroid).squaredNorm();
      if (d2 < best_d2 - 1e-12 || (d2 <= best_d2 + 1e-12 && path < best_path)) {
        best_d2 = d2;
        best_path = path;
        f->goal = grid.cellCenter(x0 + x, y0 + y);
        f->path_length = path;
        f->reachable = true;
      }
    }
    if (steps >= max_steps) continue;
    for (int k = 0; k < 8; ++k) {
      const int nx = x + kDx[k], ny = y + kDy[k];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const int ni = ny * w + nx;
      if (stamp_[ni] == stamp_counter_ || grid.cellState(x0 + nx, y0 + ny) != CellState::Free) continue;
      stamp_[ni] = stamp_counter_;
      queue_.emplace_back(ni, steps + 1);
    }
  }
}

std::optional<Eigen::Vector2d> FrontierExplorer::nextGoal(const OccupancyGrid& grid, const Eigen::Vector2d& robot_xy) {
  frontiers_.clear();
  path_ = Path();
  status_ = ExplorerStatus::Invalid;
  if (!finite(robot_xy)) return std::nullopt;
  planner_.setMap(grid);
  if (!planner_.computeDistances(robot_xy)) return std::nullopt;

  frontiers_ = findFrontiers(grid, params_.min_frontier_size);
  for (Frontier& f : frontiers_) {
    chooseGoal(grid, &f);
    f.blacklisted = isBlacklisted(f.centroid) || (f.reachable && isBlacklisted(f.goal));
    if (f.reachable) f.cost = params_.potential_scale * f.path_length - params_.gain_scale * f.size;
  }
  const auto usable = [](const Frontier& f) { return f.reachable && !f.blacklisted; };
  std::stable_sort(frontiers_.begin(), frontiers_.end(), [&](const Frontier& a, const Frontier& b) {
    if (usable(a) != usable(b)) return usable(a);
    return a.cost < b.cost;
  });
  if (frontiers_.empty() || !usable(frontiers_.front())) {
    status_ = ExplorerStatus::Complete;
    return std::nullopt;
  }
  const Eigen::Vector2d goal = frontiers_.front().goal;
  if (auto path = planner_.pathTo(goal)) path_ = std::move(*path);
  status_ = ExplorerStatus::Goal;
  return goal;
}

}  // namespace exploration
