// The building's axes, found from its walls and not assumed (DESIGN.md, "How the system sees a
// building"). Indoor walls meet at right angles in a building, so the normals of its wall lines,
// taken modulo pi/2, cluster at one angle: the building's axis. Each normal beta is mapped to the
// angle 4 beta, the same for the four directions beta + k pi/2. The axis is the direction that
// most of the line length lies along: the 4 beta around which the most length lies within
// cluster_width, and then the length-weighted circular mean of the lines within it (its angle / 4,
// in (-pi/4, pi/4]). Its agreement is that length's share of all: a wing at 30-60 deg in view, or
// furniture at other angles, is the minority and lowers it, without pulling the axis (a plain mean
// would: two wall families 45 deg apart cancel in 4 beta).
//
// HeadingBins is the one conversion between a heading and the discrete headings along the axes:
// bin k has heading axis + k 2 pi / bins.
//
// ROS-free: the standard library only.
#pragma once

#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"

namespace laser_features {

/// Discrete headings along the building's axes.
struct HeadingBins {
  double axis = 0.0;  // rad, heading of bin 0 (in whatever frame the headings are given)
  int bins = 4;       // -, a positive multiple of 4 (4: along and across the building's axes)

  double width() const { return 2.0 * kPi / bins; }
  int wrap(int bin) const { return ((bin % bins) + bins) % bins; }
  /// The heading of bin `bin` (any integer, taken modulo bins), normalized to (-pi, pi].
  double heading(int bin) const { return normalizeAngle(axis + wrap(bin) * width()); }
  /// The bin nearest to `heading` (rad).
  int bin(double heading) const { return wrap(int(std::lround(normalizeAngle(heading - axis) / width()))); }
  /// Two directions (rad) on the bins name the same way out of a node (one opening, branch or edge)
  /// within a quarter of a bin (22.5 deg with 4 bins): different ways lie a bin apart, and a measured
  /// direction (a door's normal from its hallway's walls, a heading) within a few degrees of its bin.
  double sameWayTolerance() const { return 0.25 * width(); }
  bool sameWay(double a, double b) const { return std::abs(normalizeAngle(a - b)) < sameWayTolerance(); }
};

/// The direction a hallway is followed in: a heading bin of the building's axes, and the hallway's
/// offset from the bin's heading (a wing at 30-60 deg to the axes; 0 along them).
struct BinnedDirection {
  int bin = 0;
  double offset = 0.0;  // rad
};

/// The hallway followed along `current` whose walls were seen at `walls` (rad, the bins' frame): its
/// offset from current's bin, none within `tolerance` (rad, the walls' parallel tolerance: the axis
/// itself, as the heading filter leaves it); past half a bin and half the tolerance (against flicker
/// at exactly half) the nearer bin with its offset.
BinnedDirection followWalls(const HeadingBins& bins, const BinnedDirection& current, double walls, double tolerance);

/// Parameters of BuildingAxisEstimator (each with its unit and default).
struct BuildingAxisParams {
  double min_line_length = 1.0;   // m, shorter lines are not used (furniture more often than walls)
  double max_alpha_sigma = 0.1;   // rad, lines with a larger normal uncertainty are not used
  double min_wall_length = 4.0;   // m, summed length of the used lines before the axis is taken: two
                                  // walls seen over 2 m each (a hallway's, from anywhere inside it)
  double min_agreement = 0.5;     // -, share of the line length along the axis needed: the majority
  double cluster_width = 0.0873;  // rad (5 deg), lines this close to the axis (modulo pi/2) lie along
                                  // it: several sigma_alpha of a wall line (about 1 deg)
};

/// Accumulates wall normals (in one frame) and estimates the axis of the building in that frame.
class BuildingAxisEstimator {
 public:
  explicit BuildingAxisEstimator(const BuildingAxisParams& params = BuildingAxisParams()) : params_(params) {}

  /// A line whose normal has heading `normal` (rad) in the estimator's frame, with the variance of
  /// that heading (rad^2) and the length (m) of the segment seen. Lines too short or too uncertain
  /// are ignored; returns whether it was used.
  bool add(double normal, double variance, double length);
  /// The summed length of the used lines has reached min_wall_length and they agree.
  bool ready() const {
    const Estimate e = estimate();
    return e.along >= params_.min_wall_length && e.agreement >= params_.min_agreement;
  }
  /// rad, in (-pi/4, pi/4]; 0 before any line.
  double axis() const { return estimate().axis; }
  /// -, the share in [0, 1] of the line length along the axis.
  double agreement() const { return estimate().agreement; }
  /// m, summed length of the used lines.
  double totalLength() const { return total_; }
  void clear() {
    lines_.clear();
    total_ = 0.0;
  }
  const BuildingAxisParams& params() const { return params_; }

 private:
  struct Estimate {
    double axis = 0.0, agreement = 0.0, along = 0.0;  // along: m of line length along the axis
  };
  Estimate estimate() const;

  BuildingAxisParams params_;
  std::vector<std::pair<double, double>> lines_;  // (4 beta, length) of the used lines
  double total_ = 0.0;
};

/// Where the walls of the hallway the robot stands in are taken from (each with its unit and default).
struct HallwayWallsParams {
  double min_length = 0.8;            // m, shorter lines are no hallway walls (door frames, furniture)
  double parallel_tolerance = 0.26;   // rad (15 deg), two walls of one hallway are this parallel
  double behind = 1.0, ahead = 2.5;   // m, a wall beside the robot reaches from this far behind it to this far ahead
  double min_lateral = 0.2;           // m, nearer lines are the robot's own clutter, not a wall
  double max_width = 4.1;             // m, the widest hallway with its width error (config/building.yaml)
};

/// The direction (rad, robot frame) of the hallway the robot stands in, from its walls: a line on
/// each side of the robot, beside it, parallel, the two within max_width of each other; of several
/// pairs, the narrowest (the robot's own hallway, not a wider space seen past it). Only lines within
/// `max_turn` (rad) of `reference` (rad, robot frame) are tried; the
/// direction returned is the pair's length-weighted mean, the one of its two senses nearer
/// `reference`. A wing of the building at 30-60 deg has such walls; so does a hallway along the axes.
std::optional<double> hallwayWallsDirection(const std::vector<LineSegment>& lines, double reference, double max_turn,
                                            const HallwayWallsParams& params);

/// The axis (rad, in (-pi/4, pi/4]) of a set of headings weighted by `weights` (e.g. the headings of
/// a map's hallway edges, which lie along the axes); 0 for an empty set.
double dominantAxis(const std::vector<double>& headings, const std::vector<double>& weights);

}  // namespace laser_features
