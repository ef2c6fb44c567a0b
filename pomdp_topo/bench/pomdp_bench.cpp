// One belief step of the topological localizer (predict Travel(resolution) + update with an
// observation of 3 landmarks) on synthetic grid maps of about 100, 1,000, 10,000 and 100,000 states.
// Target: <= 1 ms per step at 10,000 states on one core, linear in the state count.
//
//   pomdp_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "pomdp_topo/pomdp_localizer.h"

#include <benchmark/benchmark.h>

#include <random>

namespace pomdp_topo {
namespace {

using laser_features::kPi;

/// g x g junctions 5 m apart joined by east and north edges (10 cells each at 0.5 m); every junction
/// has an opening per hallway branch and every edge a corner and a door at random places.
TopologicalMap gridMap(int g) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  TopologicalMap map;
  std::vector<uint32_t> ids;
  for (int y = 0; y < g; ++y) {
    for (int x = 0; x < g; ++x) {
      TopoNode n;
      n.pose = {5.0 * x, 5.0 * y, 0.0};
      for (int k = 0; k < 4; ++k) {
        const bool inside = (k == 0 && x + 1 < g) || (k == 1 && y + 1 < g) || (k == 2 && x > 0) || (k == 3 && y > 0);
        if (inside) n.openings.push_back({k * kPi / 2, 1.0, 1.5, true});
      }
      ids.push_back(map.addNode(n));
    }
  }
  auto landmarks = [&]() {
    std::vector<EdgeLandmark> v(2);
    v[0].type = LandmarkType::Corner;
    v[0].distance = 0.5 + 4.0 * u(rng);
    v[0].lateral = u(rng) < 0.5 ? 1.1 : -1.1;
    v[0].orientation = v[0].lateral > 0 ? 2.4 : -2.4;
    v[0].p_lmap = 0.7;
    v[1].type = LandmarkType::Opening;
    v[1].distance = 0.5 + 4.0 * u(rng);
    v[1].lateral = u(rng) < 0.5 ? 1.0 : -1.0;
    v[1].orientation = v[1].lateral > 0 ? kPi / 2 : -kPi / 2;
    v[1].p_lmap = 0.8;
    return v;
  };
  for (int y = 0; y < g; ++y) {
    for (int x = 0; x < g; ++x) {
      if (x + 1 < g) map.addEdge(ids[y * g + x], ids[y * g + x + 1], 0.0, 5.0, landmarks());
      if (y + 1 < g) map.addEdge(ids[y * g + x], ids[(y + 1) * g + x], kPi / 2, 5.0, landmarks());
    }
  }
  return map;
}

Observation threeLandmarks() {
  Observation o;
  ObservedLandmark a, b, c;
  a.type = LandmarkType::Opening;
  a.along = 1.0;
  a.lateral = 1.0;
  a.orientation = kPi / 2;
  a.confidence = 0.9;
  b.type = LandmarkType::Corner;
  b.along = -2.0;
  b.lateral = -1.1;
  b.orientation = -2.4;
  b.confidence = 0.8;
  c.type = LandmarkType::Opening;
  c.along = 2.5;
  c.lateral = -1.0;
  c.orientation = -kPi / 2;
  c.confidence = 0.7;
  o.landmarks = {a, b, c};
  o.heading_valid = true;
  o.heading = 0.05;
  o.heading_variance = 0.01;
  return o;
}

// Grid sizes giving about 100, 1,000, 10,000 and 100,000 states.
void gridSizes(benchmark::internal::Benchmark* b) {
  for (int g : {2, 5, 16, 50}) b->Arg(g);
}

void BM_Step(benchmark::State& state) {
  const TopologicalMap map = gridMap(int(state.range(0)));
  PomdpLocalizer loc;
  loc.setMap(map);
  const Observation o = threeLandmarks();
  Action a;
  a.kind = Action::Travel;
  a.distance = loc.params().resolution;
  for (auto _ : state) {
    loc.step(a, o);
    benchmark::DoNotOptimize(loc.belief().data());
  }
  state.counters["states"] = double(loc.size());
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(loc.size()));
}
BENCHMARK(BM_Step)->Apply(gridSizes)->Unit(benchmark::kMicrosecond);

// Odometry distances that change every step: the successor lists are recomputed each time.
void BM_StepNewDistance(benchmark::State& state) {
  const TopologicalMap map = gridMap(int(state.range(0)));
  PomdpLocalizer loc;
  loc.setMap(map);
  const Observation o = threeLandmarks();
  Action a;
  a.kind = Action::Travel;
  int i = 0;
  for (auto _ : state) {
    a.distance = 0.45 + 0.001 * (i++ % 97);
    loc.step(a, o);
    benchmark::DoNotOptimize(loc.belief().data());
  }
  state.counters["states"] = double(loc.size());
}
BENCHMARK(BM_StepNewDistance)->Apply(gridSizes)->Unit(benchmark::kMicrosecond);

void BM_Update(benchmark::State& state) {
  const TopologicalMap map = gridMap(int(state.range(0)));
  PomdpLocalizer loc;
  loc.setMap(map);
  const Observation o = threeLandmarks();
  for (auto _ : state) {
    loc.update(o);
    benchmark::DoNotOptimize(loc.belief().data());
  }
  state.counters["states"] = double(loc.size());
}
BENCHMARK(BM_Update)->Apply(gridSizes)->Unit(benchmark::kMicrosecond);

void BM_SetMap(benchmark::State& state) {
  const TopologicalMap map = gridMap(int(state.range(0)));
  PomdpLocalizer loc;
  for (auto _ : state) {
    loc.setMap(map);
    benchmark::DoNotOptimize(loc.belief().data());
  }
  state.counters["states"] = double(loc.size());
}
BENCHMARK(BM_SetMap)->Apply(gridSizes)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pomdp_topo

BENCHMARK_MAIN();
