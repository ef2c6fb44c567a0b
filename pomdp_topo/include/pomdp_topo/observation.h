// What the topological localizer observes and how the robot moved, in the abstraction of the
// paper (Tomatis et al. 2001, section 3.3): actions are travel along the current heading and turns;
// observations are the landmarks (corners, openings) around the robot, expressed in a frame aligned
// with the robot's current travel heading, plus the estimated heading.
#pragma once

#include "pomdp_topo/topological_map.h"

#include <vector>

namespace pomdp_topo {

/// A landmark seen around the robot (tracked over the last scans by LandmarkTracker), in the
/// travel frame: origin at the robot, +x along the current travel heading, +y to its left.
struct ObservedLandmark {
  LandmarkType type = LandmarkType::Corner;
  double along = 0.0;        // m, + ahead of the robot
  double lateral = 0.0;      // m, + on the left
  double orientation = 0.0;  // rad, relative to the travel heading: corner bisector or opening normal
                             // (pointing away from the robot's hallway), (-pi, pi]
  double width = 0.0;        // m, openings only
  bool door = false;         // openings: a door, not a hallway's branch (BuildingRules::isDoorTracked)
  double confidence = 1.0;   // [0, 1], from the feature extractor and the number of sightings
};

struct Observation {
  std::vector<ObservedLandmark> landmarks;
  double heading = 0.0;           // rad, map frame, from the HeadingEstimator
  double heading_variance = 0.0;  // rad^2
  bool heading_valid = false;
};

/// An action between two belief updates.
struct Action {
  enum Kind : uint8_t { Travel = 0, Turn = 1 };
  Kind kind = Travel;
  double distance = 0.0;  // m, Travel: signed distance along the current heading (negative: backing up)
  int turn_bins = 0;      // Turn: heading change in heading bins (+ counter-clockwise), e.g. +1 = +90 deg
};

}  // namespace pomdp_topo
