#include "lockstep/input_gate.h"

#include <algorithm>

namespace lockstep {

InputGate::InputGate(std::vector<std::string> upstream) : upstream_(std::move(upstream)) {}

void InputGate::step(Stamp stamp, const Counts& announced) {
  if (stamp <= last_step_) return;
  last_step_ = stamp;
  steps_.emplace_back(stamp, announced);
}

void InputGate::ack(const std::string& node, Stamp stamp, const Counts& published) {
  if (std::find(upstream_.begin(), upstream_.end(), node) == upstream_.end()) return;
  UpstreamAck& a = acks_[node];
  if (stamp < a.stamp) return;
  a.stamp = stamp;
  a.published = published;
}

bool InputGate::ready(std::string* why) const {
  if (steps_.empty()) {
    if (why != nullptr) *why = "";
    return false;
  }
  const auto& [stamp, announced] = steps_.front();
  if (!covers(received_, expected(announced), watched_, why)) return false;
  for (const std::string& node : upstream_) {
    const auto a = acks_.find(node);
    if (a == acks_.end() || a->second.stamp < stamp) {
      if (why != nullptr) *why = "the acknowledgement of " + node;
      return false;
    }
    if (!covers(received_, expected(a->second.published), watched_, why)) return false;
  }
  return true;
}

Counts InputGate::expected(const Counts& announced) const {
  Counts out;
  for (const auto& [topic, n] : announced) {
    const auto s = subscriptions_.find(topic);
    if (s != subscriptions_.end()) out[topic] = n * s->second;
  }
  return out;
}

std::optional<Stamp> InputGate::takeReadyStep(std::vector<Work>* work) {
  if (!ready(nullptr)) return std::nullopt;
  const Stamp stamp = steps_.front().first;
  steps_.pop_front();
  const auto end = deferred_.upper_bound(stamp);
  for (auto it = deferred_.begin(); it != end; ++it) work->push_back(std::move(it->second));
  deferred_.erase(deferred_.begin(), end);
  return stamp;
}

std::string InputGate::waitingFor() const {
  std::string why;
  ready(&why);
  return why;
}

void InputGate::forgive() {
  if (steps_.empty()) return;
  const Stamp stamp = steps_.front().first;
  Counts announced = steps_.front().second;
  for (const std::string& node : upstream_) {
    UpstreamAck& a = acks_[node];
    if (a.stamp < stamp) a.stamp = stamp;
    announced = maxCounts(announced, a.published);
  }
  for (const auto& [topic, n] : announced) {
    if (watched_.count(topic) != 0) received_[topic] = std::max(received_[topic], n * subscriptions_.at(topic));
  }
}

}  // namespace lockstep
