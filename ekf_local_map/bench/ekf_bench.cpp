// The stochastic map's hot paths against the number of lines in a place (10, 50, 100, 200):
// one update with 10 line observations (association, stacked fusion, extents), one prediction, and
// a predict + update cycle. The maps are built by the filter itself (lines added in batches from a
// moving robot), so the covariance is dense as in real use.
// Target (issue 4): update <= 20 us at 50 lines on one core. BM_Update and BM_PredictAndUpdate use
// the update kernels this CPU selects (AVX2 + FMA where available); BM_UpdatePortableKernels forces
// the portable ones, i.e. what a CPU without AVX2 gets.
//
//   ekf_bench --benchmark_repetitions=9 --benchmark_report_aggregates_only=true
#include "ekf_local_map/odometry_noise.h"
#include "ekf_local_map/stochastic_map.h"

#include <laser_features/geometry.h>

#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <random>
#include <vector>

namespace ekf_local_map {
namespace {

using laser_features::compose;
using laser_features::kPi;

const Pose2D kSensorMount{0.12, -0.03, 0.05};
constexpr size_t kObservationsPerScan = 10;

struct Segment {
  Eigen::Vector2d a, b;
};

/// n segments: the first 10 around the place origin (seen in the benchmark scans), the others
/// scattered over a 40 m x 40 m place at random angles.
std::vector<Segment> placeSegments(size_t n, std::mt19937* rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Segment> segments;
  for (size_t i = 0; i < n; ++i) {
    const double angle = i < kObservationsPerScan ? kPi * double(i) / kObservationsPerScan + 0.05 : kPi * uniform(*rng);
    const double distance = i < kObservationsPerScan ? 1.0 + 0.3 * double(i) : 2.0 + 18.0 * uniform(*rng);
    const double bearing = 2.0 * kPi * uniform(*rng);
    const Eigen::Vector2d centre = distance * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    const Eigen::Vector2d half = 0.8 * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    segments.push_back({centre - half, centre + half});
  }
  return segments;
}

/// The observation of a segment from a sensor at `sensor_pose`, with noise drawn from its covariance.
LineSegment observe(const Segment& s, const Pose2D& sensor_pose, std::mt19937* rng) {
  std::normal_distribution<double> normal;
  const Pose2D to_sensor = laser_features::inverse(sensor_pose);
  const Eigen::Vector2d a = laser_features::transformPoint(to_sensor, s.a);
  const Eigen::Vector2d b = laser_features::transformPoint(to_sensor, s.b);
  LineSegment observation;
  Line line = laser_features::lineThroughPoints(a, b);
  line.cov << 9e-6, 1e-6, 1e-6, 1.6e-5;
  const Eigen::Vector2d noise =
      Eigen::LLT<Eigen::Matrix2d>(line.cov).matrixL() * Eigen::Vector2d(normal(*rng), normal(*rng));
  line.alpha += noise.x();
  line.r += noise.y();
  laser_features::canonicalize(&line);
  observation.line = line;
  observation.start = laser_features::projectOntoLine(line, a);
  observation.end = laser_features::projectOntoLine(line, b);
  observation.num_points = 80;
  return observation;
}

/// A place with n lines built by the filter, the robot back at its true pose, and a set of scans
/// of the first 10 lines from there.
struct Fixture {
  StochasticMap map;
  Pose2D truth;
  std::vector<std::vector<LineSegment>> scans;
  bool ok = true;

  explicit Fixture(size_t n) {
    std::mt19937 rng(42);
    const std::vector<Segment> segments = placeSegments(n, &rng);
    const OdometryNoise noise;
    truth = {0, 0, 0};
    for (size_t first = 0; first < n; first += kObservationsPerScan) {
      if (first > 0) {
        const Pose2D u{0.05, 0.0, 0.08};
        truth = compose(truth, u);
        map.predict(u, noise.covariance(u));
      }
      // Each scan sees the first 10 lines again (keeping the robot localized) and 10 new ones.
      std::vector<LineSegment> scan;
      for (size_t i = 0; i < std::min(n, first + kObservationsPerScan); ++i) {
        if (i < kObservationsPerScan || i >= first) {
          scan.push_back(observe(segments[i], compose(truth, kSensorMount), &rng));
        }
      }
      UpdateReport report;
      map.update(scan, kSensorMount, &report);
    }
    ok = map.numLines() == n;
    for (int k = 0; k < 16; ++k) {
      std::vector<LineSegment> scan;
      for (size_t i = 0; i < kObservationsPerScan; ++i) {
        scan.push_back(observe(segments[i], compose(truth, kSensorMount), &rng));
      }
      scans.push_back(scan);
    }
  }
};

void BM_Update(benchmark::State& state) {
  Fixture f(size_t(state.range(0)));
  if (!f.ok) state.SkipWithError("the fixture's map does not have the requested number of lines");
  UpdateReport report;
  size_t next = 0, matched = 0, updates = 0;
  for (auto _ : state) {
    f.map.update(f.scans[next], kSensorMount, &report);
    benchmark::DoNotOptimize(report.matched);
    matched += report.matched;
    ++updates;
    next = (next + 1) % f.scans.size();
  }
  state.counters["matched_per_scan"] = double(matched) / double(std::max<size_t>(updates, 1));
  state.counters["state_size"] = double(f.map.stateSize());
}

void BM_UpdatePortableKernels(benchmark::State& state) {
  const UpdateKernelIsa default_isa = updateKernelIsa();
  setUpdateKernelIsa(UpdateKernelIsa::kPortable);
  BM_Update(state);
  setUpdateKernelIsa(default_isa);
}

void BM_Predict(benchmark::State& state) {
  Fixture f(size_t(state.range(0)));
  const OdometryNoise noise;
  const Pose2D u{0.0, 0.0, 0.0};  // standing still: the state does not drift over the iterations
  const Eigen::Matrix3d Q = noise.covariance({0.05, 0.0, 0.08});
  for (auto _ : state) {
    f.map.predict(u, Q);
    benchmark::ClobberMemory();
  }
}

void BM_PredictAndUpdate(benchmark::State& state) {
  Fixture f(size_t(state.range(0)));
  const OdometryNoise noise;
  const Pose2D u{0.0, 0.0, 0.0};
  const Eigen::Matrix3d Q = noise.covariance({0.05, 0.0, 0.08});
  UpdateReport report;
  size_t next = 0;
  for (auto _ : state) {
    f.map.predict(u, Q);
    f.map.update(f.scans[next], kSensorMount, &report);
    benchmark::DoNotOptimize(report.matched);
    next = (next + 1) % f.scans.size();
  }
}

BENCHMARK(BM_Update)->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_UpdatePortableKernels)->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Predict)->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PredictAndUpdate)->Arg(10)->Arg(50)->Arg(100)->Arg(200)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ekf_local_map

BENCHMARK_MAIN();
