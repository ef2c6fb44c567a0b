#include "lockstep_driver.h"

#include <hybrid_slam_msgs/LockstepStep.h>
#include <ros/callback_queue.h>

#include <sstream>

namespace bullet_sim {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::ostringstream s;
  for (size_t i = 0; i < names.size(); ++i) s << (i ? ", " : "") << names[i];
  return s.str();
}

}  // namespace

namespace {

std::vector<std::string> concatenated(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

}  // namespace

LockstepDriver::LockstepDriver(ros::NodeHandle nh, const Options& options)
    : nh_(nh),
      options_(options),
      barrier_(lockstep::resolveNodeNames(nh, concatenated(options.participants, options.observers))) {
  step_pub_ = nh_.advertise<hybrid_slam_msgs::LockstepStep>("lockstep/step", 100);
  for (const std::string& node : lockstep::resolveNodeNames(nh, concatenated(options.participants, options.observers)))
    ack_subs_.push_back(nh_.subscribe(lockstep::ackTopic(node), 100, &LockstepDriver::onAck, this, lockstep::kTransportHints));
}

void LockstepDriver::onAck(const hybrid_slam_msgs::LockstepAck::ConstPtr& msg) {
  lockstep::Ack a;
  a.node = msg->node;
  a.stamp = lockstep::Stamp(msg->stamp.toNSec());
  a.wake = lockstep::Stamp(msg->wake.toNSec());
  for (size_t i = 0; i < msg->topics.size() && i < msg->counts.size(); ++i) a.published[msg->topics[i]] = msg->counts[i];
  barrier_.ack(a);
}

void LockstepDriver::publishStep(const ros::Time& stamp, bool start) {
  hybrid_slam_msgs::LockstepStep s;
  s.stamp = stamp;
  s.start = start;
  for (const auto& [topic, n] : barrier_.published(own_.counts())) {
    s.topics.push_back(topic);
    s.counts.push_back(n);
  }
  step_pub_.publish(s);
}

bool LockstepDriver::finished(lockstep::Stamp stamp, std::string* why) const {
  const auto waiting = barrier_.waitingFor(stamp);
  if (!waiting.empty()) {
    *why = "the acknowledgement of " + joined(waiting);
    return false;
  }
  return lockstep::covers(received_, barrier_.published(), watched_, why);
}

bool LockstepDriver::start(const std::function<void(const ros::Time&)>& publish_clock) {
  publish_clock_ = publish_clock;
  // Rounds of a start step until, twice in a row, every participant was known before the round and
  // acknowledged it: their subscriptions are then connected and latched messages delivered.
  const ros::WallTime begin = ros::WallTime::now();
  int complete_rounds = 0;
  for (uint32_t round = 1; ros::ok(); ++round) {
    const ros::Time stamp(0, round);
    const bool all_known = barrier_.allKnown();
    publish_clock(stamp);
    publishStep(stamp, true);
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(0.1);
    while (ros::ok() && ros::WallTime::now() < until) ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
    bool connected = true;
    for (const ros::Subscriber& s : subs_) connected = connected && s.getNumPublishers() > 0;
    complete_rounds = all_known && connected && barrier_.finished(stamp.toNSec()) ? complete_rounds + 1 : 0;
    if (complete_rounds >= 2) {
      received_ = lockstep::maxCounts(received_, barrier_.published());  // what came before counts as received
      last_step_ = stamp.toNSec();
      // An observer acknowledges start steps only (lockstep.Participant(observer=True)): excused, it
      // stays so.
      barrier_.excuse(lockstep::resolveNodeNames(nh_, options_.observers));
      ROS_INFO("bullet_sim: lockstep with %s%s (%.1f s to connect)", joined(options_.participants).c_str(),
               options_.observers.empty() ? "" : (", observed by " + joined(options_.observers)).c_str(),
               (ros::WallTime::now() - begin).toSec());
      return true;
    }
    if ((ros::WallTime::now() - begin).toSec() > 5.0)
      ROS_INFO_THROTTLE(10.0, "bullet_sim: lockstep: waiting for %s to start",
                        joined(barrier_.waitingFor(stamp.toNSec())).c_str());
  }
  return false;
}

bool LockstepDriver::wakeDue(const ros::Time& now, double tolerance) const {
  const auto wake = barrier_.nextWake(last_step_);
  return wake && *wake <= lockstep::Stamp((now + ros::Duration(tolerance)).toNSec());
}

bool LockstepDriver::step(const ros::Time& stamp) {
  const lockstep::Stamp s = stamp.toNSec();
  last_step_ = s;
  publishStep(stamp, false);
  const ros::WallTime begin = ros::WallTime::now();
  ros::WallTime last_publish = begin;
  std::string why;
  while (ros::ok() && !finished(s, &why)) {
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
    const ros::WallTime now = ros::WallTime::now();
    if ((now - last_publish).toSec() > 0.5) {
      // Again, for a participant that started late (respawned): it waits for a valid sim time first.
      publish_clock_(stamp);
      publishStep(stamp, false);
      last_publish = now;
    }
    if ((now - begin).toSec() < options_.timeout) continue;
    ROS_ERROR("bullet_sim: lockstep: the step at %.3f s waited %.0f s of wall time for %s; %s", stamp.toSec(),
              options_.timeout, why.c_str(), options_.stop_on_timeout ? "stopping" : "going on without it");
    if (options_.stop_on_timeout) return false;
    // Not waited for until it acknowledges again; what it announced counts as received.
    barrier_.excuse(barrier_.waitingFor(s));
    received_ = lockstep::maxCounts(received_, barrier_.published());
    return true;
  }
  waited_ += (ros::WallTime::now() - begin).toSec();
  ++steps_;
  return ros::ok();
}

}  // namespace bullet_sim
