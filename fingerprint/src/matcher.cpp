#include "fingerprint/matcher.h"

#include "laser_features/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace fingerprint {
namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;

// rad in [0, 2 pi): `a` measured counter-clockwise from `cut`.
double fromCut(double a, double cut) {
  const double d = std::fmod(a - cut, 2.0 * kPi);
  return d < 0.0 ? d + 2.0 * kPi : d;
}

// Where to cut `b`'s circle into a string: the middle of its widest empty arc (a pair is least likely
// to straddle it).
double cutOf(const std::vector<Feature>& b) {
  if (b.empty()) return -kPi;
  std::vector<double> v;
  for (const Feature& f : b) v.push_back(fromCut(f.bearing, -kPi));
  std::sort(v.begin(), v.end());
  double widest = v.front() + 2.0 * kPi - v.back(), cut = v.back() + 0.5 * widest;
  for (size_t k = 1; k < v.size(); ++k) {
    if (v[k] - v[k - 1] > widest) {
      widest = v[k] - v[k - 1];
      cut = v[k - 1] + 0.5 * widest;
    }
  }
  return normalizeAngle(cut - kPi);
}

}  // namespace

bool FingerprintMatcher::validate(const MatchParams& p, std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(p.gap_cost > 0.0)) return fail("match_gap_cost must be > 0");
  if (!(p.min_sigma > 0.0)) return fail("match_min_sigma must be > 0");
  return true;
}

FingerprintMatcher::FingerprintMatcher(const MatchParams& params) : params_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("fingerprint matcher: " + why);
}

bool FingerprintMatcher::sameKind(const Feature& a, const Feature& b) {
  return a.type == b.type && (a.type != FeatureType::ColorPatch || a.hue_bin == b.hue_bin);
}

Match FingerprintMatcher::align(const std::vector<Feature>& a, const std::vector<Feature>& b, double rotation) const {
  // Both circles cut into strings at the middle of b's widest empty arc; `a` turned by the rotation.
  const double cut = cutOf(b);
  std::vector<int> order(a.size()), border(b.size());
  std::iota(order.begin(), order.end(), 0);
  std::iota(border.begin(), border.end(), 0);
  std::vector<double> turned(a.size());
  for (size_t i = 0; i < a.size(); ++i) turned[i] = normalizeAngle(a[i].bearing + rotation);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return fromCut(turned[x], cut) < fromCut(turned[y], cut); });
  std::stable_sort(border.begin(), border.end(),
                   [&](int x, int y) { return fromCut(b[x].bearing, cut) < fromCut(b[y].bearing, cut); });

  // Needleman-Wunsch: cost[i][j] aligns the first i of `a` (turned) with the first j of `b`.
  const size_t n = a.size(), m = b.size();
  const double gap = params_.gap_cost, inf = std::numeric_limits<double>::infinity();
  std::vector<double> cost((n + 1) * (m + 1), inf);
  std::vector<uint8_t> step((n + 1) * (m + 1), 0);  // 1: pair, 2: gap in a, 3: gap in b
  auto at = [&](size_t i, size_t j) -> double& { return cost[i * (m + 1) + j]; };
  at(0, 0) = 0.0;
  for (size_t i = 0; i <= n; ++i) {
    for (size_t j = 0; j <= m; ++j) {
      if (i == 0 && j == 0) continue;
      double best = inf;
      uint8_t how = 0;
      if (i > 0 && at(i - 1, j) + gap < best) best = at(i - 1, j) + gap, how = 2;
      if (j > 0 && at(i, j - 1) + gap < best) best = at(i, j - 1) + gap, how = 3;
      if (i > 0 && j > 0) {
        const Feature& fa = a[order[i - 1]];
        const Feature& fb = b[border[j - 1]];
        if (sameKind(fa, fb)) {
          const double d = normalizeAngle(fb.bearing - turned[order[i - 1]]);
          const double sa = std::max(fa.sigma, params_.min_sigma), sb = std::max(fb.sigma, params_.min_sigma);
          const double pair = 0.5 * d * d / (sa * sa + sb * sb);
          // A pair costing more than two gaps is two unseen features, not one seen twice.
          if (pair < 2.0 * gap && at(i - 1, j - 1) + pair < best) best = at(i - 1, j - 1) + pair, how = 1;
        }
      }
      at(i, j) = best;
      step[i * (m + 1) + j] = how;
    }
  }
  Match out;
  out.cost = at(n, m);
  out.rotation = normalizeAngle(rotation);
  for (size_t i = n, j = m; i > 0 || j > 0;) {
    const uint8_t how = step[i * (m + 1) + j];
    if (how == 1) {
      out.paired.emplace_back(order[i - 1], border[j - 1]);
      --i, --j;
    } else if (how == 2) {
      ++out.gaps, --i;
    } else {
      ++out.gaps, --j;
    }
  }
  std::reverse(out.paired.begin(), out.paired.end());
  out.pairs = int(out.paired.size());
  return out;
}

Match FingerprintMatcher::match(const std::vector<Feature>& a, const std::vector<Feature>& b) const {
  // Every pair of one kind votes for the rotation that puts one on the other, in bins of kVoteBin;
  // the rotations of the most voted bins (with their neighbours') and none are aligned in full.
  const int bins = int(std::ceil(2.0 * kPi / kVoteBin));
  std::vector<int> votes(bins, 0);
  std::vector<double> offset_sum(bins, 0.0);  // rad, the votes' rotations from their bin's start
  for (const Feature& fa : a) {
    for (const Feature& fb : b) {
      if (!sameKind(fa, fb)) continue;
      const double r = fromCut(fb.bearing - fa.bearing, 0.0);
      const int k = std::min(bins - 1, int(r / kVoteBin));
      ++votes[k];
      offset_sum[k] += r - k * kVoteBin;
    }
  }
  std::vector<std::pair<int, int>> ranked;  // (-score, bin)
  for (int k = 0; k < bins; ++k) {
    if (votes[k] == 0) continue;
    ranked.emplace_back(-(votes[(k + bins - 1) % bins] + votes[k] + votes[(k + 1) % bins]), k);
  }
  const size_t keep = std::min(ranked.size(), size_t(kAlignedRotations));
  std::partial_sort(ranked.begin(), ranked.begin() + keep, ranked.end());
  Match best = align(a, b, 0.0);
  for (size_t i = 0; i < keep; ++i) {
    const int k = ranked[i].second;
    const Match m = align(a, b, k * kVoteBin + offset_sum[k] / votes[k]);
    if (m.cost < best.cost) best = m;
  }
  return best;
}

}  // namespace fingerprint
