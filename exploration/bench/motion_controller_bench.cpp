// One control cycle of the MotionController (31 candidate headings against a 720-point scan, the
// scan placed in the pose frame every other cycle as at 10 Hz scans / 20 Hz control), near a box.
// Target: well below 1 ms per cycle on one core.
//
//   motion_controller_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "exploration/motion_controller.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

namespace exploration {
namespace {

using laser_features::kPi;

/// A 720-beam scan from the origin facing +x: a 12 m square room and a 0.8 m box 1 m ahead.
std::vector<Eigen::Vector2d> scan720() {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 720; ++i) {
    const double a = -kPi + i * (2.0 * kPi / 720.0);
    const double c = std::cos(a), s = std::sin(a);
    double r = std::min(6.0 / std::max(std::abs(c), 1e-9), 6.0 / std::max(std::abs(s), 1e-9));
    if (c > 0.0 && std::abs(s / c) * 1.0 < 0.4) r = std::min(r, 1.0 / c);  // the box's near face
    points.emplace_back(r * c, r * s);
  }
  return points;
}

void BM_UpdateCycle(benchmark::State& state) {
  MotionParams params;
  params.candidate_headings = static_cast<int>(state.range(0));
  params.stuck_time = 1e9;  // never Blocked: the loop stays in the avoidance code
  MotionController mc(params);
  const std::vector<Eigen::Vector2d> scan = scan720();
  mc.setGoal(4.0, 0.0, std::nullopt);
  double t = 0.0;
  long cycle = 0;
  for (auto _ : state) {
    if (cycle++ % 2 == 0) mc.setScan(scan, t);
    benchmark::DoNotOptimize(mc.update(laser_features::Pose2D{}, t, 0.05, false));
    t += 0.05;
  }
  state.SetLabel(toString(mc.status()));
}
BENCHMARK(BM_UpdateCycle)->Arg(31)->Arg(91)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace exploration

BENCHMARK_MAIN();
