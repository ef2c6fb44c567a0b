// Steady-state extraction does not touch the heap: this test binary replaces the global operator
// new with a counting one, warms the extractor up, then counts the allocations of many extractions.
#include "laser_features/feature_extractor.h"

#include "synthetic_scan.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>

// The program-wide counting operator new of this binary.
#include "laser_features/testing/counting_allocator.h"

namespace {
long heapAllocations() { return laser_features::testing::allocationCount(); }
}  // namespace

namespace laser_features {
namespace {

using namespace synthetic;

TEST(NoAllocation, CounterWorks) {
  const long before = heapAllocations();
  std::vector<int>* v = new std::vector<int>(10);
  delete v;
  EXPECT_EQ(heapAllocations() - before, 2);
}

TEST(NoAllocation, SteadyStateExtractionDoesNotAllocate) {
  for (const size_t beams : {720u, 2880u}) {
    // Scans from a drive through the office and its hallway, generated before counting.
    const ScanSpec spec = ScanSpec::full(beams);
    std::mt19937 rng(1);
    std::vector<std::vector<float>> scans;
    for (int i = 0; i < 50; ++i) {
      const Pose2D pose{1.0 + 0.1 * i, 1.5 + 0.07 * i, 0.05 * i};
      scans.push_back(simulateScan(officeScene(), pose, spec, 0.01, &rng));
    }
    FeatureExtractor extractor;
    Features features;
    for (const auto& ranges : scans) extractor.extract(makeView(spec, ranges), &features);  // warm up

    const long before = heapAllocations();
    size_t lines = 0;
    for (int repeat = 0; repeat < 4; ++repeat) {
      for (const auto& ranges : scans) {
        extractor.extract(makeView(spec, ranges), &features);
        lines += features.lines.size();
      }
    }
    const long allocations = heapAllocations() - before;
    EXPECT_EQ(allocations, 0) << beams << " beams";
    EXPECT_GT(lines, 0u);
  }
}

}  // namespace
}  // namespace laser_features
