#include "lockstep/participant.h"

namespace lockstep {
namespace {

Counts toCounts(const std::vector<std::string>& topics, const std::vector<uint64_t>& counts) {
  Counts out;
  for (size_t i = 0; i < topics.size() && i < counts.size(); ++i) out[topics[i]] = counts[i];
  return out;
}

}  // namespace

std::vector<std::string> resolveNodeNames(const ros::NodeHandle& nh, const std::vector<std::string>& names) {
  std::vector<std::string> out;
  for (const std::string& n : names) out.push_back(nh.resolveName(n, false));
  return out;
}

void CountedPublishers::count(const std::string& topic) {
  for (auto& [name, count] : counts_) {
    if (name == topic) {
      ++*count;
      return;
    }
  }
  counts_.emplace_back(topic, std::make_shared<std::atomic<uint64_t>>(1));
}

Counts CountedPublishers::counts() const {
  Counts out;
  for (const auto& [topic, count] : counts_) out[topic] += count->load();
  return out;
}

Participant::Participant(ros::NodeHandle nh, const std::vector<std::string>& upstream)
    : nh_(nh), gate_(resolveNodeNames(nh, upstream)) {
  nh_.param("lockstep/enabled", enabled_, false);
  if (!enabled_) return;
  nh_.param("lockstep/timeout", timeout_, timeout_);
  // Each participant acknowledges on its own topic: only the simulator and its downstream
  // participants listen, so a step wakes no node that does not need it.
  ack_pub_ = nh_.advertise<hybrid_slam_msgs::LockstepAck>(ackTopic(ros::this_node::getName()), 100);
  step_sub_ = nh_.subscribe("lockstep/step", 100, &Participant::onStepMessage, this, kTransportHints);
  for (const std::string& node : resolveNodeNames(nh, upstream))
    ack_subs_.push_back(nh_.subscribe(ackTopic(node), 100, &Participant::onAckMessage, this, kTransportHints));
  watchdog_ = nh_.createWallTimer(ros::WallDuration(1.0), &Participant::onWatchdog, this);
  ROS_INFO("%s: lockstep with the simulator", ros::this_node::getName().c_str());
}

void Participant::onStepMessage(const hybrid_slam_msgs::LockstepStep::ConstPtr& msg) {
  step_arrivals_.emplace(msg->stamp.toNSec(), ros::WallTime::now());
  const Counts announced = toCounts(msg->topics, msg->counts);
  if (msg->start || !joined_) {
    // The start (or a node started late, e.g. respawned): acknowledge once this node's
    // subscriptions are connected to their publishers; what was published before counts as received.
    std::string why;
    if (!connected(announced, &why)) {
      ROS_INFO_THROTTLE(5.0, "%s: lockstep: waiting for %s", ros::this_node::getName().c_str(), why.c_str());
      return;
    }
    joined_ = true;
    gate_.step(msg->stamp.toNSec(), announced);
    gate_.forgive();
    if (msg->start) start_steps_.insert(msg->stamp.toNSec());
  } else {
    gate_.step(msg->stamp.toNSec(), announced);
  }
  advance();
}

void Participant::onAckMessage(const hybrid_slam_msgs::LockstepAck::ConstPtr& msg) {
  gate_.ack(msg->node, msg->stamp.toNSec(), toCounts(msg->topics, msg->counts));
  advance();
}

bool Participant::connected(const Counts& announced, std::string* why) const {
  for (const ros::Subscriber& s : subscriptions_) {
    if (announced.count(s.getTopic()) != 0 && s.getNumPublishers() == 0) {
      *why = "a publisher of " + s.getTopic();
      return false;
    }
  }
  return true;
}

void Participant::advance() {
  if (advancing_) return;  // a callback of the deferred work published: the loop below goes on
  advancing_ = true;
  std::vector<InputGate::Work> work;
  while (const auto stamp = gate_.takeReadyStep(&work)) {
    const ros::WallTime begin = ros::WallTime::now();
    for (auto& w : work) w();
    work.clear();
    ros::Time t;
    t.fromNSec(uint64_t(*stamp));
    // A start step carries no data yet: the hook waits for the first real step.
    if (hook_ && start_steps_.erase(*stamp) == 0) wake_ = hook_(t);
    acknowledge(t);
    account(*stamp, begin);
  }
  advancing_ = false;
  if (gate_.pendingStamp() != waiting_stamp_) {
    waiting_stamp_ = gate_.pendingStamp();
    waiting_since_ = ros::WallTime::now();
  }
}

void Participant::acknowledge(const ros::Time& stamp) {
  hybrid_slam_msgs::LockstepAck a;
  a.node = ros::this_node::getName();
  a.stamp = stamp;
  a.wake = wake_ > stamp ? wake_ : ros::Time();
  for (const auto& [topic, count] : published_.counts()) {
    a.topics.push_back(topic);
    a.counts.push_back(count);
  }
  ack_pub_.publish(a);
}

void Participant::account(Stamp stamp, const ros::WallTime& work_begin) {
  const ros::WallTime now = ros::WallTime::now();
  const auto arrival = step_arrivals_.find(stamp);
  if (arrival != step_arrivals_.end()) waiting_ += (work_begin - arrival->second).toSec();
  step_arrivals_.erase(step_arrivals_.begin(), step_arrivals_.upper_bound(stamp));
  working_ += (now - work_begin).toSec();
  ++steps_;
  if (report_.isZero()) report_ = now;
  if ((now - report_).toSec() < 10.0) return;
  // Which node is the run's bottleneck: the one that works longest per step.
  ROS_INFO("%s: lockstep: %lu steps, %.2f ms a step working, %.2f ms waiting for the step's inputs",
           ros::this_node::getName().c_str(), (unsigned long)steps_, 1e3 * working_ / double(steps_),
           1e3 * waiting_ / double(steps_));
  report_ = now;
}

void Participant::onWatchdog(const ros::WallTimerEvent&) {
  // Liveness only: a lost message must not hang the run. Decisions never wait on the wall clock.
  if (!gate_.hasPendingStep() || (ros::WallTime::now() - waiting_since_).toSec() < timeout_) return;
  ROS_ERROR("%s: lockstep step at %.3f s waited %.0f s of wall time for %s; going on without it",
            ros::this_node::getName().c_str(), double(gate_.pendingStamp()) * 1e-9, timeout_, gate_.waitingFor().c_str());
  gate_.forgive();
  advance();
}

}  // namespace lockstep
