// The simulator's side of lockstep (rate 0): each step's sensor data go out with a LockstepStep, and
// sim time does not pass the step until every participant has acknowledged it and what they
// published in it (cmd_vel) has arrived. See the lockstep package for the participants' side.
#pragma once

#include <hybrid_slam_msgs/LockstepAck.h>
#include <ros/ros.h>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lockstep/participant.h"
#include "lockstep/step_barrier.h"

namespace bullet_sim {

class LockstepDriver {
 public:
  struct Options {
    std::vector<std::string> participants;  // node names, resolved like topics
    std::vector<std::string> observers;     // nodes the first step waits for, none after (an evaluation)
    double timeout = 10.0;                  // (s, wall) before a silent participant is reported
    bool stop_on_timeout = false;           // false: report it and go on
  };

  LockstepDriver(ros::NodeHandle nh, const Options& options);

  /// A publisher whose messages the steps announce; its queue never drops (lockstep::kUnboundedQueue).
  template <class M>
  lockstep::Publisher advertise(ros::NodeHandle& nh, const std::string& topic, bool latch = false) {
    return own_.advertise<M>(nh, topic, lockstep::kUnboundedQueue, latch);
  }
  /// A subscription of the simulator's whose messages the participants announce (cmd_vel): call
  /// received() from its callback.
  void watch(const ros::Subscriber& sub) { watched_.insert(sub.getTopic()); subs_.push_back(sub); }
  void received(const std::string& topic) { ++received_[topic]; }

  /// Waits until every participant and observer has connected (sim time stays at a few nanoseconds
  /// meanwhile, published by `publish_clock`); then no step waits for the observers. False when ROS
  /// shuts down.
  bool start(const std::function<void(const ros::Time&)>& publish_clock);
  /// A participant asked for a step at or before `now` (within `tolerance` seconds).
  bool wakeDue(const ros::Time& now, double tolerance) const;
  /// Announces the step and waits for it to be finished. False: stop the simulation (a participant
  /// stayed silent past the timeout with stop_on_timeout).
  bool step(const ros::Time& stamp);
  /// Wall time spent waiting for the participants (s), and the steps made.
  double waited() const { return waited_; }
  uint64_t steps() const { return steps_; }

 private:
  void onAck(const hybrid_slam_msgs::LockstepAck::ConstPtr& msg);
  void publishStep(const ros::Time& stamp, bool start);
  bool finished(lockstep::Stamp stamp, std::string* why) const;

  ros::NodeHandle nh_;
  Options options_;
  lockstep::StepBarrier barrier_;
  lockstep::CountedPublishers own_;
  std::set<std::string> watched_;
  std::vector<ros::Subscriber> subs_;
  lockstep::Counts received_;
  lockstep::Stamp last_step_ = 0;
  double waited_ = 0.0;
  uint64_t steps_ = 0;
  std::function<void(const ros::Time&)> publish_clock_;
  ros::Publisher step_pub_;
  std::vector<ros::Subscriber> ack_subs_;
};

}  // namespace bullet_sim
