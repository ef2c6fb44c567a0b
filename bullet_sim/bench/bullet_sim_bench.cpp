// Simulator benchmarks: laser rays per second (tree ray caster vs the naive btCollisionWorld::rayTest
// per beam), the real-time factor of the simulator core with 720 beams at 10 Hz, and the panoramic
// camera's frames per second (720 x 120, one core; target >= 30).
//   rosrun bullet_sim bullet_sim_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "bullet_sim/panoramic_camera.h"
#include "bullet_sim/simulator.h"

using namespace bullet_sim;

namespace {

const World& world(const std::string& name) {
  static std::map<std::string, World> cache;
  auto it = cache.find(name);
  if (it == cache.end()) it = cache.emplace(name, loadWorldFile(std::string(WORLDS_DIR) + "/" + name + ".yaml")).first;
  return it->second;
}

// Free poses (>= 0.3 m from obstacles) spread over the world, fixed seed.
std::vector<Pose2> freePoses(const World& w, size_t n) {
  Vec2 lo, hi;
  w.bounds(&lo, &hi);
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(lo.x, hi.x), uy(lo.y, hi.y), ua(-M_PI, M_PI);
  std::vector<Pose2> out;
  while (out.size() < n) {
    const Pose2 p{ux(rng), uy(rng), ua(rng)};
    if (w.regionAt({p.x, p.y}) >= 0 && distanceToObstacles(w, {p.x, p.y}) > 0.3) out.push_back(p);
  }
  return out;
}

constexpr int kBeams = 720;
constexpr double kRange = 15.0;

void BM_TreeRayCaster(benchmark::State& state, const std::string& name) {
  const RayCaster2D caster(world(name));
  const auto poses = freePoses(world(name), 256);
  std::vector<float> ranges(kBeams);
  size_t i = 0;
  for (auto _ : state) {
    const Pose2& p = poses[i++ % poses.size()];
    caster.castFan(p.x, p.y, p.yaw - M_PI, 2 * M_PI / kBeams, kBeams, kRange, ranges.data());
    benchmark::DoNotOptimize(ranges.data());
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kBeams,
                                                    benchmark::Counter::kIsRate);
  state.counters["primitives"] = static_cast<double>(caster.primitiveCount());
}

// Both cores: two threads cast the scans of different poses.
void BM_TreeRayCasterTwoThreads(benchmark::State& state, const std::string& name) {
  const RayCaster2D caster(world(name));
  const auto poses = freePoses(world(name), 256);
  const int scans_per_thread = 64;
  for (auto _ : state) {
    auto work = [&](int offset) {
      std::vector<float> ranges(kBeams);
      for (int k = 0; k < scans_per_thread; ++k) {
        const Pose2& p = poses[(offset + 2 * k) % poses.size()];
        caster.castFan(p.x, p.y, p.yaw - M_PI, 2 * M_PI / kBeams, kBeams, kRange, ranges.data());
        benchmark::DoNotOptimize(ranges.data());
      }
    };
    std::thread t0(work, 0), t1(work, 1);
    t0.join();
    t1.join();
  }
  state.counters["rays_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * 2 * scans_per_thread * kBeams, benchmark::Counter::kIsRate);
}

// The naive baseline: one btCollisionWorld::rayTest per beam against the box-shaped walls.
void BM_BulletRayTestPerBeam(benchmark::State& state, const std::string& name) {
  const CollisionWorld bullet(world(name), 0.25);
  const auto poses = freePoses(world(name), 256);
  size_t i = 0;
  for (auto _ : state) {
    const Pose2& p = poses[i++ % poses.size()];
    for (int b = 0; b < kBeams; ++b) {
      const double a = p.yaw - M_PI + b * 2 * M_PI / kBeams;
      benchmark::DoNotOptimize(bullet.rayTest(p.x, p.y, std::cos(a), std::sin(a), kRange));
    }
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()) * kBeams,
                                                    benchmark::Counter::kIsRate);
  state.counters["objects"] = static_cast<double>(bullet.objectCount());
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One simulated second per iteration: 100 physics steps (motion swept against the world, odometry),
// 10 scans of 720 beams with noise. The counter is simulated seconds per wall second.
void BM_SimulatorRealTimeFactor(benchmark::State& state, const std::string& name) {
  const RobotModel robot = robotModelFromUrdf(readFile(URDF_PATH), "base_link", "laser");
  Simulator sim(world(name), robot, SimParams{});
  std::vector<float> ranges;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uw(-1.0, 1.0);
  const int steps_per_scan = 10;
  for (auto _ : state) {
    sim.setCommand(0.5, uw(rng));
    for (int s = 0; s < 100; ++s) {
      sim.step();
      if (s % steps_per_scan == 0) sim.scan(&ranges);
    }
    if (sim.bumper()) sim.reset();
  }
  state.counters["real_time_factor"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                          benchmark::Counter::kIsRate);
}

// One image per iteration from poses spread over the world, the camera 0.8 m high: 720 column casts,
// 86,400 pixels shaded, with or without the per-channel noise (`state.range(0)`: 1 = noise).
void BM_PanoramicCamera(benchmark::State& state, const std::string& name) {
  const RayCaster2D caster(world(name));
  CameraParams params;
  if (state.range(0) == 0) params.noise_stddev = 0.0;
  PanoramicCamera camera(world(name), caster, params, 1);
  const auto poses = freePoses(world(name), 64);
  std::vector<uint8_t> rgb;
  size_t i = 0;
  for (auto _ : state) {
    camera.render(poses[i++ % poses.size()], 0.8, &rgb);
    benchmark::DoNotOptimize(rgb.data());
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                      benchmark::Counter::kIsRate);
}

}  // namespace

BENCHMARK_CAPTURE(BM_PanoramicCamera, institute, std::string("institute"))->Arg(1)->Arg(0)->UseRealTime();
BENCHMARK_CAPTURE(BM_PanoramicCamera, large_floor, std::string("large_floor"))->Arg(1)->UseRealTime();
BENCHMARK_CAPTURE(BM_TreeRayCaster, institute, std::string("institute"))->UseRealTime();
BENCHMARK_CAPTURE(BM_TreeRayCaster, large_floor, std::string("large_floor"))->UseRealTime();
BENCHMARK_CAPTURE(BM_TreeRayCasterTwoThreads, institute, std::string("institute"))->UseRealTime();
BENCHMARK_CAPTURE(BM_BulletRayTestPerBeam, institute, std::string("institute"))->UseRealTime();
BENCHMARK_CAPTURE(BM_BulletRayTestPerBeam, large_floor, std::string("large_floor"))->UseRealTime();
BENCHMARK_CAPTURE(BM_SimulatorRealTimeFactor, institute, std::string("institute"))->UseRealTime();

BENCHMARK_MAIN();
