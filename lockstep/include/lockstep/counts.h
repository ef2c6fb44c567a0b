// Message counts of lockstep (ROS-free): how many messages were published or received per topic.
// A receiver has everything a step depends on when, on each topic it subscribes to, it has received
// as many messages as the publishers announced: counting, not arrival order, decides, so thread
// scheduling and the order in which separate connections deliver cannot change a decision.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <string>

namespace lockstep {

/// Sim time in nanoseconds (ros::Time::toNSec), exact to compare.
using Stamp = int64_t;
/// Messages per resolved topic name.
using Counts = std::map<std::string, uint64_t>;

/// True when `received` reaches `announced` on every topic of `watched`; otherwise false and, when
/// `why` is given, the first topic short ("/features: 41 of 42").
bool covers(const Counts& received, const Counts& announced, const std::set<std::string>& watched,
            std::string* why = nullptr);

/// The larger of the two counts on each topic of either.
Counts maxCounts(const Counts& a, const Counts& b);

/// The sum of the two counts on each topic of either (publishers of one topic add up).
Counts sumCounts(const Counts& a, const Counts& b);

}  // namespace lockstep
