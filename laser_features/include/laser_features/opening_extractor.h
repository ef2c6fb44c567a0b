// Openings a robot can pass (doors, hallway branches): the places where Tomatis, Nourbakhsh &
// Siegwart 2001 switch between the topological and the metric map. Three cues, each with a check
// that the gap is free and deep enough:
//  (a) range discontinuities: a jump from near to far (or to no return) between neighbouring valid
//      beams; the opening spans from the near edge point to the nearest point on the far side;
//  (b) gaps between collinear segments (two pieces of one wall with a door between them);
//  (c) in a hallway, "large steps perpendicular to the direction of motion": a gap between two pieces
//      of the same side wall, parallel to the hallway axis, possibly offset (a side branch).
// A gap found by several cues is reported once, preferring (b), then (c), then (a).
#pragma once

#include "laser_features/building_rules.h"
#include "laser_features/geometry.h"
#include "laser_features/line_extractor.h"
#include "laser_features/place_classifier.h"
#include "laser_features/scan.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace laser_features {

enum class OpeningKind : uint8_t { kUnknown = 0, kDoor = 1, kJunction = 2 };
enum class OpeningSource : uint8_t { kRangeDiscontinuity = 0, kCollinearGap = 1, kHallwayStep = 2 };

struct Opening {
  Eigen::Vector2d left = Eigen::Vector2d::Zero();    // m, edge on the left looking along theta
  Eigen::Vector2d right = Eigen::Vector2d::Zero();   // m, edge on the right looking along theta
  Eigen::Vector2d center = Eigen::Vector2d::Zero();  // m, midpoint of the edges
  double theta = 0.0;  // rad, normal through the opening, pointing away from the sensor
  double width = 0.0;  // m, passable width
  OpeningKind kind = OpeningKind::kUnknown;  // door (BuildingRules::isDoor), junction, or unknown
                                             // (one edge is no wall end: an occlusion gap)
  bool room_behind = false;  // the free space seen behind it reaches past its edges (see BuildingRules)
  OpeningSource source = OpeningSource::kRangeDiscontinuity;
  // Set in a wall: a wall piece (a line) runs on from one of its edges along its line (every (b);
  // OpeningExtractor::inWall). The gaps between furniture legs have no wall beside them.
  bool in_wall = false;
  // [0, 1]: how deep the free space behind the opening is (saturating at 2 minDepth()) times how well
  // its edges are supported (by wall segments for (a) and (b), 0.8 for (c)); halved for (a) when the
  // far edge is not a wall end.
  double confidence = 0.0;
};

/// Parameters of OpeningExtractor (each with its unit and default).
struct OpeningExtractorParams {
  double robot_radius = 0.25;       // m, openings narrower than 2 robot_radius, or with less free space
                                    // than that behind them, are never reported
  BuildingRules rules;              // door widths: the narrowest opening reported is the narrowest
                                    // door, the widest the widest hallway's mouth (a branch off the
                                    // hallway); which are doors (BuildingRules::isDoor)
  double jump_min = 0.5;            // m, range jump between neighbouring beams that starts cue (a)
  double collinear_chi2 = 13.82;    // -, (b): same line if chi^2 (2 dof) below this (99.9 %) ...
  double collinear_angle = 0.0524;  // rad (3 deg), ... or if |d alpha| and ...
  double collinear_distance = 0.05; // m, ... |d r| are both below these
  double line_tolerance = 0.05;     // m, beams ending this close to the opening line hit its edge
  double min_line_distance = 0.1;   // m, openings whose line passes closer to the sensor are skipped
  double max_range_fraction = 0.9;  // -, (a): a near edge beyond this fraction of range_max is where the
                                    //   scanner stops seeing a wall, not where the wall ends
  double hallway_parallel_angle = 0.1745;  // rad (10 deg), (c): wall pieces this parallel to the axis
  double hallway_step_max_offset = 0.5;    // m, (c): largest lateral offset between the two pieces
  double duplicate_distance = 0.3;  // m, openings with centres closer than this are the same
};

class OpeningExtractor {
 public:
  using Params = OpeningExtractorParams;

  explicit OpeningExtractor(const Params& params = Params());
  const Params& params() const { return params_; }
  /// Pre-sizes the work buffers for scans of up to `beams` beams.
  void reserve(size_t beams);

  /// Fills `openings` (cleared first). `lines` are the segments of the same scan; `place` gives the
  /// hallway axis for cue (c).
  void extract(const ScanPoints& points, const std::vector<LineSegment>& lines,
               const PlaceEstimate& place, std::vector<Opening>* openings);

 private:
  /// What the beams between the two edges of a candidate opening see.
  struct Passage {
    bool clear = false;
    double depth = 0.0;  // m, deepest point behind the opening line (infinite for a no-return beam)
    bool room_behind = false;  // at least kRoomBeams points behind it lie beyond its edges
  };
  static constexpr int kRoomBeams = 2;  // one stray return is no room

  double minWidth() const;
  /// m, the free space needed behind an opening's line: the robot's diameter, so that it fits through.
  double minDepth() const { return 2.0 * params_.robot_radius; }
  /// The widest opening reported: a branch as wide as the widest hallway, with its width error.
  double maxWidth() const { return params_.rules.widestHallway(); }
  void labelBeams(const ScanPoints& points, const std::vector<LineSegment>& lines);
  Eigen::Vector2d segmentEdge(const ScanPoints& points, const LineSegment& segment, bool at_end) const;
  Eigen::Vector2d beamEdge(const ScanPoints& points, const std::vector<LineSegment>& lines,
                           size_t beam, int outward) const;
  bool isJumpEdge(const ScanPoints& points, size_t beam, int towards) const;
  Passage checkPassage(const ScanPoints& points, const Eigen::Vector2d& edge_a,
                       const Eigen::Vector2d& edge_b, const Line& opening_line) const;
  bool makeOpening(const ScanPoints& points, const Eigen::Vector2d& edge_a, const Eigen::Vector2d& edge_b,
                   OpeningSource source, double support, Opening* opening) const;
  void addIfNew(const Opening& opening, std::vector<Opening>* openings) const;
  bool inWall(const Opening& opening, const std::vector<LineSegment>& lines) const;

  void findCollinearGaps(const ScanPoints& points, const std::vector<LineSegment>& lines,
                         std::vector<Opening>* openings) const;
  void findHallwaySteps(const ScanPoints& points, const std::vector<LineSegment>& lines,
                        const PlaceEstimate& place, std::vector<Opening>* openings) const;
  void findRangeDiscontinuities(const ScanPoints& points, const std::vector<LineSegment>& lines,
                                std::vector<Opening>* openings) const;
  void searchFarSide(const ScanPoints& points, const std::vector<LineSegment>& lines, size_t near,
                     int direction, std::vector<Opening>* openings) const;

  Params params_;
  std::vector<int32_t> beam_line_;  // per beam: index of the line segment it belongs to, or -1
};

}  // namespace laser_features
