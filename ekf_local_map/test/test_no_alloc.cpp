// Steady-state filtering does not touch the heap: this test binary replaces the global operator
// new with a counting one, warms a map up, then counts the allocations of many predict + update
// cycles (including scans with unmatched and rejected observations and the second association pass).
#include "ekf_local_map/stochastic_map.h"

#include "simulated_room.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>

// The program-wide counting operator new of this binary.
#include "laser_features/testing/counting_allocator.h"

namespace {
long heapAllocations() { return laser_features::testing::allocationCount(); }
}  // namespace

namespace ekf_local_map {
namespace {

using laser_features::compose;
using namespace testing_support;

TEST(NoAllocation, CounterWorks) {
  const long before = heapAllocations();
  std::vector<int>* v = new std::vector<int>(10);
  delete v;
  EXPECT_EQ(heapAllocations() - before, 2);
}

TEST(NoAllocation, SteadyStatePredictAndUpdateDoNotAllocate) {
  const Pose2D mount{0.12, -0.03, 0.05};
  std::mt19937 rng(1);
  const OdometryNoise noise = testOdometryNoise();
  // A bigger place than the room: the room's lines plus 40 lines out of sight of the gate.
  std::vector<TrueSegment> world = officeRoom();
  for (int i = 0; i < 40; ++i) {
    const double y = 4.0 + 0.3 * i;
    world.push_back({{-2.0 + 0.1 * (i % 7), y}, {1.0 + 0.1 * (i % 5), y + 0.05 * (i % 3)}});
  }
  // Scans prepared before counting: the room's lines, some with a bad covariance or NaN, and a
  // line never seen before (a new line: the map grows within its capacity).
  const TrueSegment extra{{-1.0, -1.2}, {1.0, -1.2}};  // a low bench along the bottom wall
  std::vector<Pose2D> increments;
  std::vector<std::vector<LineSegment>> scans;
  Pose2D truth{0, 0, 0};
  for (int step = 0; step < 120; ++step) {
    const Pose2D u = arcIncrement(0.05, 0.0625);
    truth = compose(truth, u);
    increments.push_back(noisyIncrement(u, noise, &rng));
    std::vector<LineSegment> scan = observeAll(officeRoom(), truth, mount, &rng);
    if (step % 10 == 3) scan[1].line.cov(0, 0) = -1.0;
    if (step % 10 == 7) scan[2].line.r = std::numeric_limits<double>::quiet_NaN();
    if (step >= 60) scan.push_back(observeSegment(extra, 3, compose(truth, mount), &rng));
    scans.push_back(scan);
  }
  StochasticMapParams params = testParams();
  params.initial_line_capacity = 64;
  StochasticMap map(params);
  map.update(observeAll(world, {0, 0, 0}, mount, &rng), mount, nullptr);
  UpdateReport report;
  // Warm up: buffers reach their steady-state sizes (a scan with more observations than any
  // later one, all rejected, sizes the per-observation buffers).
  std::vector<LineSegment> wide(12);
  for (LineSegment& s : wide) s.line.r = std::numeric_limits<double>::quiet_NaN();
  map.update(wide, mount, &report);
  for (int step = 0; step < 20; ++step) {
    map.predict(increments[size_t(step)], noise.covariance(increments[size_t(step)]));
    map.update(scans[size_t(step)], mount, &report);
  }

  const long before = heapAllocations();
  size_t matched = 0, new_lines = 0;
  for (size_t step = 20; step < scans.size(); ++step) {
    map.predict(increments[step], noise.covariance(increments[step]));
    map.update(scans[step], mount, &report);
    matched += report.matched;
    new_lines += report.new_lines;
  }
  const long allocations = heapAllocations() - before;
  EXPECT_EQ(allocations, 0);
  EXPECT_GT(matched, 500u);
  EXPECT_EQ(new_lines, 1u);  // the bench, added once, then matched
}

}  // namespace
}  // namespace ekf_local_map
