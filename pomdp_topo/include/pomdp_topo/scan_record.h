// What the map builder needs of one scan (FrontEnd's output and state after it), kept to replay the
// scans of a rejected loop hypothesis.
#pragma once

#include "laser_features/geometry.h"
#include "pomdp_topo/front_end.h"
#include "pomdp_topo/observation.h"

#include <vector>

namespace pomdp_topo {

struct ScanRecord {
  std::vector<Action> actions;
  Observation observation;
  std::vector<PassedLandmark> passed;
  double travel = 0.0;         // FrontEnd::travel() after the scan
  laser_features::Pose2D pose;  // FrontEnd::pose() after the scan
  int heading_bin = 0;         // FrontEnd::headingBin() after the scan
};

}  // namespace pomdp_topo
