// A 2-D log-odds occupancy grid built from laser scans, for the frontier-exploration baseline
// (Thrun, Burgard & Fox, Probabilistic Robotics, ch. 9: the binary Bayes filter per cell, with the
// inverse sensor model of a beam: free cells up to the return, an occupied cell at it).
//
// Cells: cell (ix, iy) covers [ix res, (ix+1) res) x [iy res, (iy+1) res) in the map frame. The
// indices are global (floor(x / res)): they stay valid when the grid grows. Each cell is one byte
// (what bytes() reports is the real memory of the map): the log-odds in steps of
// max(|l_min|, l_max) / 127 as a signed byte, -128 meaning "never observed". The increments round
// to whole steps (with the defaults: step 0.0276, l_occ 0.854, l_free -0.413).
//
// The inverse sensor model treats a scan as the polygon of its returns (the beams alone leave
// holes: beyond res / angle_increment, 2.9 m for 1 deg and 5 cm, adjacent beams are more than a
// cell apart, and every hole would be a frontier):
//  - a beam marks free the cells it crosses (Bresenham) and occupied the cell of its return;
//  - two adjacent returns on one surface (the adaptive breakpoint test of Borges & Aldon 2004, as in
//    laser_features' line extractor; or, seen too grazing for it, in line with a third adjacent
//    return; never more than max_surface_gap apart) make the wedge between them free (the cells
//    whose centres lie in the triangle sensor-return-return) and the chord between the returns
//    occupied (else a wall seen from afar is dotted, and its unseen cells between the dots are
//    frontiers, or holes for the planner in a thin wall);
//  - adjacent returns not joined but on one surface line (its direction from the chords of the
//    returns joined to either): the wedge is free up to 1.2 cells across the surface, and a beam
//    skimming that surface before its return stops its free cells as far (else a wall seen at a
//    grazing angle is erased by the beams skimming it);
//  - across a break, the wedge is free up to the nearer return, 1.2 cells short of its surface
//    (facing the sensor if its direction is unknown).
// One scan updates each cell at most once (a cell crossed by many beams near the sensor is one
// observation, not hundreds), and a cell occupied by the scan is not also updated as free by it
// (as OctoMap's insertion, Hornung et al. 2013).
//
// ROS-free: Eigen, laser_features' geometry and the standard library only.
#pragma once

#include "laser_features/geometry.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace exploration {

struct OccupancyGridParams {
  double resolution = 0.05;           // m, side of a cell
  double l_occ = 0.85;                // -, log-odds added to a cell at a return (p = 0.70)
  double l_free = -0.4;               // -, log-odds added to a cell a beam crossed (p = 0.40)
  double l_min = -2.0;                // -, clamp (p = 0.12): a free cell turns occupied after 4 hits
  double l_max = 3.5;                 // -, clamp (p = 0.97): an occupied cell turns free after 9 misses
  double occupied_threshold = 0.65;   // -, probability at or above which an observed cell is Occupied
  double free_threshold = 0.45;       // -, probability at or below which an observed cell is Free
                                      // (above the 0.40 of one miss: a cell seen once is Free)
  double max_range = 15.0;            // m, a return at or beyond this is no hit: free up to max_range
  double min_range = 0.0;             // m, ranges at or below this are skipped (the sensor's range_min)
  double no_return_free_range = 5.0;  // m, a +inf range (no return) marks free space this far (capped
                                      // at max_range); 0: such beams mark nothing. Set it at most at
                                      // the range the sensor surely sees (a missing return says
                                      // nothing is nearer)
  bool fill_gaps = true;              // -, the wedges between adjacent beams (and the surfaces between
                                      // adjacent returns) are filled (see above); false: beams only
  double breakpoint_lambda = 0.1745;  // rad (10 deg), adjacent returns are one surface when their
                                      // range difference is within what a surface seen at this
                                      // grazing angle gives (laser_features' LineParams: the same)
  double breakpoint_margin = 0.03;    // m, range noise allowed on top of that; also how far a third
                                      // return may lie off the line of two (grazing surfaces)
  double max_surface_gap = 1.0;       // m, returns farther apart are never joined (bounds a false
                                      // chord across a depth step; a door seen so edge-on that no
                                      // beam enters it is closed until seen better: 3 misses reopen)
  double grow_margin = 1.0;           // m, a growing grid extends this much beyond what a scan needs
                                      // (fewer reallocations; counts in bytes())
  std::size_t max_cells = 16u << 20;  // -, a growing grid refuses scans that would need more cells
                                      // (16 Mi cells: 200 m x 200 m at 5 cm, 16 MiB)
};

/// Axis-aligned bounds of a fixed-size grid, m, map frame.
struct GridBounds {
  double min_x = 0.0;
  double min_y = 0.0;
  double max_x = 0.0;
  double max_y = 0.0;
};

enum class CellState : std::uint8_t { Unknown, Free, Occupied };

const char* toString(CellState state);

/// A cell's global indices.
struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex& o) const { return x == o.x && y == o.y; }
  bool operator!=(const CellIndex& o) const { return !(*this == o); }
};

class OccupancyGrid {
 public:
  /// A grid that starts empty and grows to cover the scans. Throws std::invalid_argument when
  /// validate() refuses `params`.
  explicit OccupancyGrid(const OccupancyGridParams& params = OccupancyGridParams());
  /// A grid of fixed extent covering `bounds`; what falls outside is dropped. Throws
  /// std::invalid_argument for invalid params or bounds (non-finite, empty, too many cells).
  OccupancyGrid(const OccupancyGridParams& params, const GridBounds& bounds);
  static bool validate(const OccupancyGridParams& params, std::string* error = nullptr);
  const OccupancyGridParams& params() const { return params_; }

  /// Inserts one scan: beam i has the bearing angle_min + i * angle_increment in the sensor frame,
  /// whose pose in the map is `sensor_in_map`. Ranges that are NaN, -inf or <= min_range are
  /// skipped; +inf is no return (free up to no_return_free_range); a range >= max_range is free up
  /// to max_range without a hit. Returns false (and writes nothing) for a non-finite pose or angle,
  /// or when a growing grid would exceed max_cells; `error` says why.
  bool insertScan(const laser_features::Pose2D& sensor_in_map, const std::vector<float>& ranges,
                  double angle_min, double angle_increment, std::string* error = nullptr);
  bool insertScan(const laser_features::Pose2D& sensor_in_map, const std::vector<double>& ranges,
                  double angle_min, double angle_increment, std::string* error = nullptr);

  /// Sets a cell to the clamp of its state (Free: l_min, Occupied: l_max, Unknown: never observed),
  /// growing the grid if needed (a fixed grid: false outside). For maps from other sources and tests.
  bool setCell(int ix, int iy, CellState state);

  /// Unknown outside the grid and for cells never observed or with a probability between the
  /// thresholds (conflicting evidence).
  CellState cellState(int ix, int iy) const;
  CellState cellState(const CellIndex& c) const { return cellState(c.x, c.y); }
  CellState stateAt(const Eigen::Vector2d& p) const { return cellState(worldToCell(p)); }
  /// Occupancy probability; 0.5 for cells never observed or outside the grid.
  double probability(int ix, int iy) const;
  /// Whether the cell was ever updated (inside the grid).
  bool observed(int ix, int iy) const;

  /// The cell containing p (any finite point; the cell may be outside the grid).
  CellIndex worldToCell(const Eigen::Vector2d& p) const;
  /// Centre of a cell, m.
  Eigen::Vector2d cellCenter(int ix, int iy) const;
  Eigen::Vector2d cellCenter(const CellIndex& c) const { return cellCenter(c.x, c.y); }
  bool contains(int ix, int iy) const {
    return ix >= min_x_ && iy >= min_y_ && ix < min_x_ + width_ && iy < min_y_ + height_;
  }

  double resolution() const { return params_.resolution; }
  bool fixedBounds() const { return fixed_; }
  /// Extent, cells: the grid covers [minX(), minX() + width()) x [minY(), minY() + height()).
  int minX() const { return min_x_; }
  int minY() const { return min_y_; }
  int width() const { return width_; }
  int height() const { return height_; }
  /// The map-frame corner of cell (minX(), minY()), m (a nav_msgs/OccupancyGrid's origin).
  Eigen::Vector2d origin() const { return cellCenter(min_x_, min_y_).array() - 0.5 * resolution(); }
  std::size_t cellCount() const { return cells_.size(); }
  /// Memory of the map's cells: one byte each.
  std::size_t bytes() const { return cells_.size() * sizeof(std::int8_t); }
  /// Cells in `state` (a scan of the grid).
  std::size_t count(CellState state) const;
  /// Scans inserted (accepted).
  std::size_t scansInserted() const { return scans_; }

  /// The cells as a nav_msgs/OccupancyGrid's data: row-major from (minX(), minY()), -1 never
  /// observed, else the probability in percent.
  void toOccupancyData(std::vector<std::int8_t>* data) const;

  /// Row-major index of an in-grid cell (callers check contains()).
  std::size_t index(int ix, int iy) const {
    return static_cast<std::size_t>(iy - min_y_) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(ix - min_x_);
  }

 private:
  template <typename T>
  bool insert(const laser_features::Pose2D& pose, const std::vector<T>& ranges, double angle_min,
              double angle_increment, std::string* error);
  bool ensureCovers(int x0, int y0, int x1, int y1, std::string* error);  // inclusive cell box
  template <typename Visit>
  static void bresenham(const CellIndex& from, const CellIndex& to, Visit visit);
  void traceFree(const CellIndex& from, const CellIndex& to, bool include_end);
  void traceHits(const CellIndex& from, const CellIndex& to);
  void fillTriangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);
  void applyUpdates();
  CellState classify(std::int8_t v) const;

  // The pieces of insert(), in order, on the scan's rays_.
  struct Ray;
  struct BeamOrder;
  void joinSurfaces(const BeamOrder& order, double angle_increment);  // joined_
  void surfaceTangents(const BeamOrder& order);  // each return's Ray::tangent
  /// The direction of the surface through both returns when one's known surface, extended, passes
  /// through the other's (a surface seen too grazing, or too sparsely, to be joined); else zero.
  Eigen::Vector2d sharedTangent(const Ray& a, const Ray& b) const;
  /// How far before a's return free space must stop so that no cell the surface through it (of
  /// direction t; unknown: facing the sensor) may cross is marked free.
  double pullback(const Ray& a, const Eigen::Vector2d& t) const;
  void traceBeams(const BeamOrder& order, const Eigen::Vector2d& sensor, const CellIndex& origin);  // each beam
  void fillWedges(const BeamOrder& order, const Eigen::Vector2d& sensor);  // between adjacent beams (fill_gaps)

  OccupancyGridParams params_;
  bool fixed_ = false;
  double step_ = 0.0;                                  // log-odds per quantization level
  int d_occ_ = 0, d_free_ = 0, v_min_ = 0, v_max_ = 0;  // in levels
  double l_occ_thr_ = 0.0, l_free_thr_ = 0.0;          // the thresholds as log-odds

  int min_x_ = 0, min_y_ = 0, width_ = 0, height_ = 0;
  std::vector<std::int8_t> cells_;
  std::size_t scans_ = 0;

  // Per scan (kept: no allocation per scan in steady state): the beams in the map frame, the cells
  // to update (as indices).
  struct Ray {
    bool valid = false;
    bool hit = false;
    double length = 0.0;                              // m, free (and with a hit: the return)
    Eigen::Vector2d dir = Eigen::Vector2d::Zero();    // unit, map frame
    Eigen::Vector2d end = Eigen::Vector2d::Zero();    // m, map frame
    CellIndex cell;                                   // of `end`
    Eigen::Vector2d tangent = Eigen::Vector2d::Zero();  // the surface's direction at the return
                                                        // (unit; zero: not joined to any)
  };
  // The beams' order in a scan: the next and the previous beam (`n`: none); a full turn wraps round.
  struct BeamOrder {
    std::size_t n = 0;
    bool wraps = false;
    std::size_t next(std::size_t i) const { return i + 1 < n ? i + 1 : (wraps ? 0 : n); }
    std::size_t prev(std::size_t i) const { return i > 0 ? i - 1 : (wraps ? n - 1 : n); }
  };
  std::vector<Ray> rays_;
  std::vector<std::uint8_t> joined_;  // joined_[i]: beam i and the next are one surface
  std::vector<std::size_t> hits_, misses_;
};

}  // namespace exploration
