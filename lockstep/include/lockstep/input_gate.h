// A lockstep participant's side (ROS-free): the steps the simulator announced, what this node has
// received, and the work deferred until a step's inputs have all arrived.
//
// A step at sim time s is ready when, on every topic the node subscribes to, it has received as many
// messages as the step announced (the simulator's sensor data and every participant's output of the
// steps before), and as many as each upstream participant (one whose output of the same step this
// node uses, e.g. pomdp_topo's belief for the coordinator) announced when it acknowledged s. Then the
// work deferred with stamps up to s runs, in stamp order, and the node acknowledges s.
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "lockstep/counts.h"

namespace lockstep {

class InputGate {
 public:
  using Work = std::function<void()>;

  explicit InputGate(std::vector<std::string> upstream = {});

  /// A subscription of this node's, with counting. Two subscriptions of one topic each receive
  /// every message: the topic then counts twice per message.
  void watch(const std::string& topic) {
    watched_.insert(topic);
    ++subscriptions_[topic];
  }
  const std::set<std::string>& watched() const { return watched_; }
  /// A counted message arrived on `topic`.
  void received(const std::string& topic) { ++received_[topic]; }
  /// A step of the simulator; one not newer than the last is ignored.
  void step(Stamp stamp, const Counts& announced);
  /// A participant's acknowledgement; only upstream ones matter.
  void ack(const std::string& node, Stamp stamp, const Counts& published);
  /// Work to run once the step at `stamp` (or a later one) is ready.
  void defer(Stamp stamp, Work work) { deferred_.emplace(stamp, std::move(work)); }

  /// The oldest announced step whose inputs have all arrived: its stamp, with the deferred work up to
  /// it appended to `work` in stamp order (ties in arrival order). None while it still waits.
  std::optional<Stamp> takeReadyStep(std::vector<Work>* work);
  /// What the oldest step waits for ("/features: 41 of 42", "ack of /pomdp_topo"); empty if none.
  std::string waitingFor() const;
  /// Gives up waiting for what the oldest step lacks: its announced counts are taken as received
  /// (a lost message, or messages published before this node was connected).
  void forgive();
  bool hasPendingStep() const { return !steps_.empty(); }
  Stamp pendingStamp() const { return steps_.empty() ? -1 : steps_.front().first; }

 private:
  struct UpstreamAck {
    Stamp stamp = -1;
    Counts published;
  };
  bool ready(std::string* why) const;
  /// What the node must have received for `announced` messages: each, on each subscription.
  Counts expected(const Counts& announced) const;

  std::vector<std::string> upstream_;
  std::set<std::string> watched_;
  std::map<std::string, uint64_t> subscriptions_;  // per watched topic
  Counts received_;
  std::deque<std::pair<Stamp, Counts>> steps_;
  Stamp last_step_ = -1;
  std::map<std::string, UpstreamAck> acks_;
  std::multimap<Stamp, Work> deferred_;
};

}  // namespace lockstep
