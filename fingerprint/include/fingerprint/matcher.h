// Matching two fingerprints by global alignment with uncertainty (Tapus & Siegwart, section 4: a
// modified global alignment of two circular strings, the cost of a pairing from the features'
// bearing uncertainty, gaps for what one sees and the other does not).
//
// The fingerprints are circular lists ordered by bearing. For each rotation that puts a feature of
// the first onto one of the same kind in the second (and no rotation at all), the first is turned by
// it and the two lists are aligned in order (Needleman-Wunsch): a pair of one kind costs its
// squared bearing difference in standard deviations of that difference, half of it (a negative
// log-likelihood: (d theta)^2 / 2 (sigma_a^2 + sigma_b^2)); a feature left unpaired costs gap_cost
// (occluded, or not seen by the other). Two colour patches pair only in one hue bin. The least
// cost over the rotations is the match; the rotation is the robot's heading change between the two.
// The rotations are first voted for: every pair of one kind votes for the rotation that puts one on
// the other, in bins of kVoteBin (wider than the bearings' deviations of a few hundredths of a
// radian, so that the true rotation's votes fall in one bin or two); the full alignment is made for
// the kAlignedRotations most voted bins (a bin's score counts its neighbours' votes too) at their
// votes' mean rotation, and for no rotation. The right rotation pairs most features, and so is voted
// for most.
//
// ROS-free: the standard library.
#pragma once

#include "fingerprint/visual_features.h"

#include <string>
#include <utility>
#include <vector>

namespace fingerprint {

/// Parameters of FingerprintMatcher (config/fingerprint.yaml's match_* keys; each with its unit and default).
struct MatchParams {
  double gap_cost = 4.5;        // -, a feature unpaired: as much as a pair 3 standard deviations apart
  double min_sigma = 0.01;      // rad, a bearing's least deviation (a feature's own may be tiny: an edge's is a column's)
};

/// The best alignment of two fingerprints.
struct Match {
  double cost = 0.0;      // -, its negative log-likelihood (pairs' and gaps' costs)
  double rotation = 0.0;  // rad, the turn of the first that aligns it: bearing_b = bearing_a + rotation
  int pairs = 0;          // features paired
  int gaps = 0;           // features left unpaired, in either
  std::vector<std::pair<int, int>> paired;  // (index in a, index in b)
};

class FingerprintMatcher {
 public:
  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit FingerprintMatcher(const MatchParams& params = MatchParams());
  static bool validate(const MatchParams& params, std::string* error = nullptr);
  const MatchParams& params() const { return params_; }

  /// The least-cost alignment of `a` and `b` over the most voted rotations (see the top of the file)
  /// and none. Two empty fingerprints match at cost 0.
  Match match(const std::vector<Feature>& a, const std::vector<Feature>& b) const;
  /// The alignment of `a` turned by `rotation` (rad) with `b`, in order of bearing.
  Match align(const std::vector<Feature>& a, const std::vector<Feature>& b, double rotation) const;

  /// Two features may pair: one kind, and for colour patches one hue bin.
  static bool sameKind(const Feature& a, const Feature& b);

  static constexpr int kAlignedRotations = 8;  // rotations aligned in full, of the most voted bins
  static constexpr double kVoteBin = 0.05;     // rad, a rotation vote's bin

 private:
  MatchParams params_;
};

}  // namespace fingerprint
