#include "lockstep/step_barrier.h"

#include <algorithm>

namespace lockstep {

StepBarrier::StepBarrier(const std::vector<std::string>& participants)
    : order_(participants), states_(participants.size()) {}

bool StepBarrier::ack(const Ack& a) {
  const auto it = std::find(order_.begin(), order_.end(), a.node);
  if (it == order_.end()) return false;
  State& s = states_[size_t(it - order_.begin())];
  if (s.known && a.stamp < s.stamp) return true;
  s.known = true;
  s.excused = false;
  s.stamp = a.stamp;
  s.wake = a.wake;
  s.published = a.published;  // a restarted node counts from zero again
  return true;
}

bool StepBarrier::finished(Stamp stamp) const { return waitingFor(stamp).empty(); }

std::vector<std::string> StepBarrier::waitingFor(Stamp stamp) const {
  std::vector<std::string> out;
  for (size_t i = 0; i < order_.size(); ++i) {
    if (!states_[i].excused && (!states_[i].known || states_[i].stamp < stamp)) out.push_back(order_[i]);
  }
  return out;
}

std::optional<Stamp> StepBarrier::nextWake(Stamp after) const {
  std::optional<Stamp> best;
  for (const State& s : states_) {
    if (s.known && s.wake > after && (!best || s.wake < *best)) best = s.wake;
  }
  return best;
}

void StepBarrier::excuse(const std::vector<std::string>& nodes) {
  for (const std::string& n : nodes) {
    const auto it = std::find(order_.begin(), order_.end(), n);
    if (it != order_.end()) states_[size_t(it - order_.begin())].excused = true;
  }
}

Counts StepBarrier::published(const Counts& own) const {
  Counts out = own;
  for (const State& s : states_) out = sumCounts(out, s.published);
  return out;
}

}  // namespace lockstep
