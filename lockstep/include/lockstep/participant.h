// A node's side of the simulator's lockstep (ROS). With the global parameter `lockstep/enabled`
// false or absent — a real robot, a replayed bag, the simulator paced by `rate` — every wrapper here
// passes straight through and nothing waits. With it true (bullet_sim with rate 0), the node:
//  - counts what it publishes (lockstep::Publisher) and what it receives (subscribe());
//  - runs its sensor-driven callbacks (Delivery::Gated) only when the simulator's step of their
//    stamp has all its inputs (see InputGate), in stamp order, then its step hook, and acknowledges
//    the step on `<node>/lockstep_ack` with what it has published and when it next wants a step of its own.
// All of this runs on the callback queue of the node handle given (the node's one spinning thread).
#pragma once

#include <hybrid_slam_msgs/LockstepAck.h>
#include <hybrid_slam_msgs/LockstepStep.h>
#include <ros/message_traits.h>
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

#include "lockstep/input_gate.h"

namespace lockstep {

/// For every subscription whose data a lockstep step waits for, tf included: without TCP_NODELAY,
/// Nagle's algorithm holds a small message back until the peer acknowledges the last one.
inline const ros::TransportHints kTransportHints = ros::TransportHints().tcpNoDelay();

/// roscpp's queue size for "never drop" (a subscription's and a publisher's queue alike). In
/// lockstep every counted message must arrive: a step waits until its counts are received, so a
/// message a full queue dropped would stall the step until the timeout. While a node is busy (a
/// service call during a step) its queue grows by what the others publish, and the simulator waits
/// for that node, so the queue stays bounded by one step's messages.
constexpr uint32_t kUnboundedQueue = 0;

/// The first multiple of `period` (s) after `t`: the sim time a periodic step hook asks for next, on
/// the same grid as a ros::Timer of that period.
inline ros::Time nextMultiple(const ros::Time& t, double period) {
  return ros::Time((std::floor(t.toSec() / period + 1e-6) + 1.0) * period);
}

/// The topic a participant acknowledges steps on: `<its resolved node name>/lockstep_ack`.
inline std::string ackTopic(const std::string& node) { return node + "/lockstep_ack"; }

/// A ros::Publisher that counts its messages for the acknowledgements.
class Publisher {
 public:
  Publisher() = default;
  Publisher(ros::Publisher pub, std::shared_ptr<std::atomic<uint64_t>> count) : pub_(std::move(pub)), count_(std::move(count)) {}
  template <class M>
  void publish(const M& msg) const {
    pub_.publish(msg);
    if (count_) ++*count_;
  }
  uint32_t getNumSubscribers() const { return pub_.getNumSubscribers(); }
  std::string getTopic() const { return pub_.getTopic(); }

 private:
  ros::Publisher pub_;
  std::shared_ptr<std::atomic<uint64_t>> count_;
};

/// The publishers of one node whose messages lockstep announces, and their counts so far.
class CountedPublishers {
 public:
  template <class M>
  Publisher advertise(ros::NodeHandle& nh, const std::string& topic, uint32_t queue, bool latch = false) {
    ros::Publisher pub = nh.advertise<M>(topic, queue, latch);
    auto count = std::make_shared<std::atomic<uint64_t>>(0);
    counts_.emplace_back(pub.getTopic(), count);
    return Publisher(pub, count);
  }
  /// Counts a message published on `topic` (a resolved name) by a publisher not made here (an
  /// action server's result): announced like the others.
  void count(const std::string& topic);
  /// Messages published so far on each topic.
  Counts counts() const;

 private:
  std::vector<std::pair<std::string, std::shared_ptr<std::atomic<uint64_t>>>> counts_;
};

/// Node names resolved as topics are (namespaces, remappings), as acknowledgements carry them.
std::vector<std::string> resolveNodeNames(const ros::NodeHandle& nh, const std::vector<std::string>& names);

enum class Delivery {
  Immediate,  // the callback runs when the message arrives (state: a belief, a map, a status)
  Gated,      // sensor data with a header: the callback runs at the step of its stamp
};

class Participant {
 public:
  /// `upstream`: the participants (node names, resolved like topics) whose output of a step this
  /// node uses within the same step.
  explicit Participant(ros::NodeHandle nh, const std::vector<std::string>& upstream = {});

  bool enabled() const { return enabled_; }

  /// How long (s, wall) to wait for a transform at a message's stamp: in lockstep the step's tf is
  /// published before its data and always comes, so a busy machine must not make a node skip data
  /// (2 s, liveness only); otherwise `configured`.
  double transformTimeout(double configured) const { return enabled_ ? std::max(configured, 2.0) : configured; }

  template <class M>
  Publisher advertise(ros::NodeHandle& nh, const std::string& topic, uint32_t queue, bool latch = false) {
    return published_.advertise<M>(nh, topic, enabled_ ? kUnboundedQueue : queue, latch);
  }

  template <class M>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue,
                            std::function<void(const boost::shared_ptr<const M>&)> callback,
                            Delivery delivery = Delivery::Immediate,
                            const ros::TransportHints& hints = ros::TransportHints()) {
    const std::string resolved = nh.resolveName(topic);
    gate_.watch(resolved);
    // In lockstep every counted message goes through the queue of the participant's node handle.
    ros::NodeHandle& on = enabled_ ? nh_ : nh;
    // Nagle's algorithm would hold a step's small messages back for the peer's delayed ACK.
    ros::TransportHints transport = enabled_ ? ros::TransportHints(hints).tcpNoDelay() : hints;
    ros::Subscriber sub = on.subscribe<M>(
        topic, enabled_ ? kUnboundedQueue : queue,
        [this, resolved, callback, delivery](const boost::shared_ptr<const M>& msg) {
          if (!enabled_) return callback(msg);
          gate_.received(resolved);
          if constexpr (ros::message_traits::HasHeader<M>::value) {
            if (delivery == Delivery::Gated) gate_.defer(msg->header.stamp.toNSec(), [callback, msg] { callback(msg); });
            else callback(msg);
          } else {
            callback(msg);  // only stamped messages can be gated
          }
          advance();
        },
        ros::VoidConstPtr(), transport);
    subscriptions_.push_back(sub);
    return sub;
  }

  template <class M, class T>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue,
                            void (T::*method)(const boost::shared_ptr<const M>&), T* object,
                            Delivery delivery = Delivery::Immediate,
                            const ros::TransportHints& hints = ros::TransportHints()) {
    return subscribe<M>(nh, topic, queue, [object, method](const boost::shared_ptr<const M>& m) { (object->*method)(m); },
                        delivery, hints);
  }

  /// A message this node published on `topic` (resolved through `nh`) through a publisher it does
  /// not own — an action server's result —: its next acknowledgement announces it, so a downstream
  /// participant that counts the topic has it at the next step. Lockstep only.
  void published(const ros::NodeHandle& nh, const std::string& topic) {
    if (enabled_) published_.count(nh.resolveName(topic));
  }

  /// Runs at every step, after the step's gated callbacks, with the step's stamp; returns the next
  /// sim time the node must act at by itself (ros::Time() for none). Lockstep only.
  void onStep(std::function<ros::Time(const ros::Time&)> hook) { hook_ = std::move(hook); }

 private:
  void onStepMessage(const hybrid_slam_msgs::LockstepStep::ConstPtr& msg);
  void onAckMessage(const hybrid_slam_msgs::LockstepAck::ConstPtr& msg);
  void advance();
  bool connected(const Counts& announced, std::string* why) const;
  void acknowledge(const ros::Time& stamp);
  void onWatchdog(const ros::WallTimerEvent&);
  void account(Stamp stamp, const ros::WallTime& work_begin);

  ros::NodeHandle nh_;
  bool enabled_ = false;
  double timeout_ = 10.0;
  InputGate gate_;
  CountedPublishers published_;
  std::vector<ros::Subscriber> subscriptions_;
  std::function<ros::Time(const ros::Time&)> hook_;
  ros::Time wake_;
  ros::Publisher ack_pub_;
  ros::Subscriber step_sub_;
  std::vector<ros::Subscriber> ack_subs_;
  ros::WallTimer watchdog_;
  ros::WallTime waiting_since_;
  Stamp waiting_stamp_ = -1;
  bool advancing_ = false;
  std::map<Stamp, ros::WallTime> step_arrivals_;  // wall time each step message came
  double working_ = 0.0, waiting_ = 0.0;            // (s, wall) over all steps, for the report
  uint64_t steps_ = 0;
  ros::WallTime report_;
  bool joined_ = false;
  std::set<Stamp> start_steps_;  // acknowledged without running the hook  // the first step since this node started was acknowledged
};

}  // namespace lockstep
