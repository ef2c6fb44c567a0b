// MapBuilder in LoopCheck mode: a new node that looks like an old one, the two hypotheses tracked
// until one dominates, then the nodes merged or the new stretch kept. The class: map_builder.h.
#include "pomdp_topo/map_builder.h"

#include <limits>

namespace pomdp_topo {

// ---- Loop closing (Tapus & Siegwart: two belief peaks tracked until one remains) -------------

bool MapBuilder::startLoopCheck(uint32_t new_node, uint32_t previous_node, const Scan& scan) {
  const int go_bin = departure_bin_ >= 0 ? departure_bin_ : frontier_bin_;
  const double gate = params_.loop_gate_base + params_.loop_gate_per_m * travel_since_localized_;
  // scan.travel - s_: the travel when the robot was at the new node.
  if (!loop_.begin(*map_, params_, headingBins(), new_node, previous_node, binHeading(frontier_bin_), go_bin, gate,
                   scan.travel - s_)) {
    return false;
  }
  mode_ = Mode::LoopCheck;
  buffer_.clear();
  std::string names;
  for (const uint32_t c : loop_.candidates()) names += " " + std::to_string(c);
  event(TopoEvent::Kind::LoopHypothesis,
        "loop hypothesis: node " + std::to_string(new_node) + " may be node(s)" + names + "; map building paused",
        int(new_node));
  return true;
}

void MapBuilder::processLoopCheck(const Scan& scan, const FrontEnd& fe) {
  buffer_.push_back(scan);
  const bool turned =
      loop_.observe(*map_, params_, headingBins(), fe_params_.tracks.pass_lag, scan.passed, scan.actions, scan.travel);
  const double u = scan.travel - loop_.travel0();
  const double odds = loopLogOdds();
  if (odds >= params_.loop_decision_log_odds) {
    decideLoop(true, fe);
  } else if (-odds >= params_.loop_decision_log_odds) {
    decideLoop(false, fe);
  } else if (turned || u >= params_.loop_verify_distance) {
    decideLoop(odds > 0.0, fe);
  }
}

void MapBuilder::decideLoop(bool old_wins, const FrontEnd& fe) {
  std::vector<Scan> scans;
  scans.swap(buffer_);
  if (old_wins) {
    const uint32_t keep = loop_.bestNode();
    const double odds = loopLogOdds();
    const std::string evidence = loopEvidence();
    loop_.clear();
    std::vector<std::pair<uint32_t, uint32_t>> zipped;
    // Zips only within the position gate (when on): positions share the dead reckoning's frame.
    map_->mergeNodes(keep, loop_.newNode(), &zipped,
                     params_.position_gate > 0.0 ? params_.position_gate : std::numeric_limits<double>::infinity());
    loops_.emplace_back(keep, loop_.newNode());
    event(TopoEvent::Kind::LoopClosed,
          "loop closed: node " + std::to_string(loop_.newNode()) + " merged into node " + std::to_string(keep) +
              " (log odds " + std::to_string(odds) + "; " + evidence + ")",
          int(loop_.newNode()), int(keep));
    for (const auto& [kept, dropped] : zipped) {
      event(TopoEvent::Kind::NodesMerged,
            "node " + std::to_string(dropped) + " merged into node " + std::to_string(kept) +
                ": the same place, on the stretch the loop closed along",
            int(dropped), int(kept));
    }
    // Continue on the known graph from the old node, replaying the motion since.
    becomeLocalizedAt(keep, loop_.bin());
    for (const Scan& s : scans) {
      for (const Action& a : s.actions) localizer_->predict(a);
    }
    if (!scans.empty()) localizer_->update(scans.back().observation);
    pending_.clear();
    return;
  }
  ++loops_rejected_;
  event(TopoEvent::Kind::LoopRejected,
        "loop hypothesis rejected: node " + std::to_string(loop_.newNode()) + " is a new place (log odds " +
            std::to_string(loopLogOdds()) + "; " + loopEvidence() + ")",
        int(loop_.newNode()));
  loop_.clear();
  if (loop_.bin() != frontier_bin_) {
    // Turned at the new junction: the new stretch starts there, along the branch taken.
    startFrontier(loop_.newNode(), loop_.bin(), 0.0, loop_.travel0());
  } else {
    mode_ = Mode::Frontier;
  }
  for (const Scan& s : scans) dispatch(s, fe);
}

}  // namespace pomdp_topo
