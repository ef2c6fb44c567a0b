// The simulator's side of lockstep (ROS-free): which participant has finished which step, what each
// has published, and when one of them next needs a step of its own (a control period).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "lockstep/counts.h"

namespace lockstep {

/// A participant's acknowledgement of a step.
struct Ack {
  std::string node;
  Stamp stamp = 0;   // the step finished
  Stamp wake = 0;    // the next sim time it must act at by itself; 0: only when data come
  Counts published;  // cumulative, per topic
};

class StepBarrier {
 public:
  explicit StepBarrier(const std::vector<std::string>& participants);

  /// Records an acknowledgement; false (ignored) for a node that is not a participant. An older
  /// acknowledgement than one already recorded changes nothing; a newer one replaces its counts (a
  /// restarted node counts from zero).
  bool ack(const Ack& a);
  /// Every participant has acknowledged `stamp` or a later step.
  bool finished(Stamp stamp) const;
  /// The participants that have not acknowledged `stamp` yet.
  std::vector<std::string> waitingFor(Stamp stamp) const;
  /// The earliest wake-up a participant asked for that lies after `after`; none if none did.
  std::optional<Stamp> nextWake(Stamp after) const;
  /// What the participants have published (their latest acknowledgements), plus `own`.
  Counts published(const Counts& own = {}) const;
  /// Not waited for until they acknowledge again (silent past the timeout: stopped, or restarting).
  void excuse(const std::vector<std::string>& nodes);
  /// Every participant has acknowledged at least once.
  bool allKnown() const { return waitingFor(0).empty(); }

 private:
  struct State {
    bool known = false;
    bool excused = false;
    Stamp stamp = 0;
    Stamp wake = 0;
    Counts published;
  };
  std::vector<std::string> order_;
  std::vector<State> states_;
};

}  // namespace lockstep
