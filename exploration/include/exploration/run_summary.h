// The exploration run's summary: one JSON object (exploration_node's ~summary_file, read by
// scripts/benchmark_exploration and scripts/evaluate). ROS-free.
#pragma once

#include <string>

#include "exploration/coordinator.h"

namespace exploration {

/// What a run did: complete or not, the map's places, nodes and openings, the coordinator's
/// counts, travel (m), sim and wall time (s), and the final text. One line, newline-terminated.
std::string runSummaryJson(const Coordinator& coordinator, bool complete, const std::string& text, double sim_s,
                           double wall_s);

/// `text` as a JSON string's content: quotes, backslashes and control characters escaped.
std::string jsonEscape(const std::string& text);

}  // namespace exploration
