// Full feature extraction (lines + corners + openings + place type) on synthetic 360-degree scans of
// an office with two doors, furniture, a pillar and a hallway, at 361, 720, 1440 and 2880 beams.
// Target: <= 50 us per 720-beam scan on one core, linear in the beam count.
//
//   feature_extractor_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "laser_features/feature_extractor.h"

#include "../test/synthetic_scan.h"

#include <benchmark/benchmark.h>

#include <random>
#include <vector>

namespace laser_features {
namespace {

using namespace synthetic;

/// Scans along a drive through the office and into the hallway, 1 cm range noise.
std::vector<std::vector<float>> officeDrive(const ScanSpec& spec, int count) {
  std::mt19937 rng(42);
  std::vector<std::vector<float>> scans;
  for (int i = 0; i < count; ++i) {
    const double t = double(i) / double(count);
    const Pose2D pose = t < 0.7 ? Pose2D{1.0 + 4.0 * t / 0.7, 1.5 + 1.0 * t / 0.7, 0.3 * i}
                                : Pose2D{3.45, 4.2 + 2.0 * (t - 0.7) / 0.3, 0.3 * i};
    scans.push_back(simulateScan(officeScene(), pose, spec, 0.01, &rng));
  }
  return scans;
}

void BM_FullExtraction(benchmark::State& state) {
  const ScanSpec spec = ScanSpec::full(size_t(state.range(0)));
  const std::vector<std::vector<float>> scans = officeDrive(spec, 32);
  FeatureExtractor extractor;
  Features features;
  size_t next = 0, lines = 0, corners = 0, openings = 0, scans_done = 0;
  for (auto _ : state) {
    const ScanView view = makeView(spec, scans[next]);
    const bool ok = extractor.extract(view, &features);
    benchmark::DoNotOptimize(ok);
    benchmark::DoNotOptimize(features.lines.data());
    lines += features.lines.size();
    corners += features.corners.size();
    openings += features.openings.size();
    ++scans_done;
    next = (next + 1) % scans.size();
  }
  state.SetItemsProcessed(int64_t(scans_done) * state.range(0));  // beams per second
  state.counters["lines"] = double(lines) / double(scans_done);
  state.counters["corners"] = double(corners) / double(scans_done);
  state.counters["openings"] = double(openings) / double(scans_done);
}
BENCHMARK(BM_FullExtraction)->Arg(361)->Arg(720)->Arg(1440)->Arg(2880)->Unit(benchmark::kMicrosecond);

// The line extractor alone, for the share of the total.
void BM_LinesOnly(benchmark::State& state) {
  const ScanSpec spec = ScanSpec::full(size_t(state.range(0)));
  const std::vector<std::vector<float>> scans = officeDrive(spec, 32);
  ScanPoints points;
  LineExtractor extractor;
  std::vector<LineSegment> lines;
  size_t next = 0;
  for (auto _ : state) {
    points.assign(makeView(spec, scans[next]));
    extractor.extract(points, &lines);
    benchmark::DoNotOptimize(lines.data());
    next = (next + 1) % scans.size();
  }
}
BENCHMARK(BM_LinesOnly)->Arg(720)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace laser_features

BENCHMARK_MAIN();
