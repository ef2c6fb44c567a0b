// The building's axes, found from its walls and not assumed (DESIGN.md, "How the system sees a
// building"). Indoor walls meet at right angles in a building, so the normals of its wall lines,
// taken modulo pi/2, cluster at one angle: the building's axis. Each normal beta is mapped to the
// unit vector (cos 4 beta, sin 4 beta), which is the same for the four directions beta + k pi/2;
// the length-weighted mean of these vectors gives the axis (its angle / 4, in (-pi/4, pi/4]) and
// their agreement (its length R in [0, 1]: 1 when every line lies on the axes; lines at random
// angles, such as furniture, lower it by their share of the length).
//
// HeadingBins is the one conversion between a heading and the discrete headings along the axes:
// bin k has heading axis + k 2 pi / bins.
//
// ROS-free: the standard library only.
#pragma once

#include <cmath>
#include <vector>

#include "laser_features/geometry.h"

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
};

/// Parameters of BuildingAxisEstimator (each with its unit and default).
struct BuildingAxisParams {
  double min_line_length = 1.0;   // m, shorter lines are not used (furniture more often than walls)
  double max_alpha_sigma = 0.1;   // rad, lines with a larger normal uncertainty are not used
  double min_wall_length = 4.0;   // m, summed length of the used lines before the axis is taken: two
                                  // walls seen over 2 m each (a hallway's, from anywhere inside it)
  double min_agreement = 0.8;     // -, agreement R needed: walls on the axes with up to ~20 % of the
                                  // line length at other angles (furniture, a wing at 30-60 deg)
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
  bool ready() const { return total_ >= params_.min_wall_length && agreement() >= params_.min_agreement; }
  /// rad, in (-pi/4, pi/4]; 0 before any line.
  double axis() const;
  /// -, R in [0, 1].
  double agreement() const { return total_ > 0.0 ? std::hypot(c_, s_) / total_ : 0.0; }
  /// m, summed length of the used lines.
  double totalLength() const { return total_; }
  void clear() { c_ = s_ = total_ = 0.0; }
  const BuildingAxisParams& params() const { return params_; }

 private:
  BuildingAxisParams params_;
  double c_ = 0.0, s_ = 0.0, total_ = 0.0;
};

/// The axis (rad, in (-pi/4, pi/4]) of a set of headings weighted by `weights` (e.g. the headings of
/// a map's hallway edges, which lie along the axes); 0 for an empty set.
double dominantAxis(const std::vector<double>& headings, const std::vector<double>& weights);

}  // namespace laser_features
