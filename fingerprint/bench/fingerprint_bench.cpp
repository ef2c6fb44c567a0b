// Fingerprint benchmarks: the visual features of one 720 x 120 panorama (target <= 2 ms), a whole
// fingerprint with 40 laser features, and matching two fingerprints of about 30 features (one
// node's likelihood).
//   rosrun fingerprint fingerprint_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>

#include "fingerprint/fingerprint.h"
#include "fingerprint/matcher.h"

using namespace fingerprint;

namespace {

// A panorama of walls: stretches of 10-80 columns, each its own muted colour, shaded by a smooth
// factor, floor and ceiling outside the middle half, noise sigma 2 - what the simulator renders.
cv::Mat wallsPanorama(uint32_t seed) {
  const PanoramaModel m;
  cv::Mat img(m.height, m.width, CV_8UC3);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> len(10, 80), level(60, 220);
  std::normal_distribution<double> noise(0.0, 2.0);
  int c = 0;
  while (c < m.width) {
    const int n = std::min(len(rng), m.width - c);
    const cv::Vec3d color(level(rng), level(rng), level(rng));
    for (int j = c; j < c + n; ++j) {
      const double shade = 0.7 + 0.3 * std::cos((j - c) * 3.14159 / n);
      for (int r = 0; r < m.height; ++r) {
        const bool wall = r >= m.height / 4 && r < 3 * m.height / 4;
        const cv::Vec3d v = wall ? color * shade : (r < m.height / 4 ? cv::Vec3d(230, 230, 225) : cv::Vec3d(120, 110, 100));
        for (int k = 0; k < 3; ++k) img.at<cv::Vec3b>(r, j)[k] = cv::saturate_cast<uint8_t>(v[k] + noise(rng));
      }
    }
    c += n;
  }
  return img;
}

void BM_VisualFeatures(benchmark::State& state) {
  VisualFeatureExtractor x;
  const PanoramaModel m;
  std::vector<cv::Mat> images;
  for (uint32_t s = 0; s < 8; ++s) images.push_back(wallsPanorama(s));
  std::vector<Feature> f;
  size_t i = 0, features = 0;
  for (auto _ : state) {
    f.clear();
    x.extract(images[i++ % images.size()], m, &f);
    features += f.size();
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["features"] = double(features) / double(state.iterations());
}

void BM_WholeFingerprint(benchmark::State& state) {
  VisualFeatureExtractor x;
  const PanoramaModel m;
  const cv::Mat image = wallsPanorama(1);
  std::vector<Feature> f;
  const Eigen::Matrix2d cov = Eigen::Matrix2d::Identity() * 1e-4;
  for (auto _ : state) {
    f.clear();
    x.extract(image, m, &f);
    for (int k = 0; k < 40; ++k)
      f.push_back(laserCorner(Pose2{0.05, 0.0, 0.0}, Eigen::Vector2d(3.0 * std::cos(k), 3.0 * std::sin(k)), cov, 0.9));
    sortByBearing(&f);
    benchmark::DoNotOptimize(f.data());
  }
}

// Two views of the walls panorama 0.3 rad apart with the laser's corners: about 30 features each.
void BM_MatchTwoFingerprints(benchmark::State& state) {
  VisualFeatureExtractor x;
  const PanoramaModel m;
  const cv::Mat image = wallsPanorama(3);
  std::vector<Feature> a;
  x.extract(image, m, &a);
  const Eigen::Matrix2d cov = Eigen::Matrix2d::Identity() * 1e-4;
  for (int k = 0; k < 8; ++k)
    a.push_back(laserCorner(Pose2{0.05, 0.0, 0.0}, Eigen::Vector2d(3.0 * std::cos(k), 3.0 * std::sin(k)), cov, 0.9));
  sortByBearing(&a);
  std::vector<Feature> b = a;
  for (Feature& f : b) f.bearing = std::remainder(f.bearing + 0.3, 2.0 * M_PI);
  sortByBearing(&b);
  const FingerprintMatcher matcher;
  for (auto _ : state) benchmark::DoNotOptimize(matcher.match(a, b).cost);
  state.counters["features"] = double(a.size());
}

}  // namespace

BENCHMARK(BM_MatchTwoFingerprints)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_VisualFeatures)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_WholeFingerprint)->Unit(benchmark::kMicrosecond)->UseRealTime();

BENCHMARK_MAIN();
