#include "local_poses.h"

#include <tf2/utils.h>

#include <cmath>
#include <cstdlib>
#include <string>

#include "laser_features/planar_covariance.h"

namespace exploration {

using laser_features::Pose2D;

namespace {
Pose2D poseOf(const geometry_msgs::PoseWithCovarianceStamped& msg) {
  return {msg.pose.pose.position.x, msg.pose.pose.position.y, tf2::getYaw(msg.pose.pose.orientation)};
}
}  // namespace

void LocalPoses::add(const geometry_msgs::PoseWithCovarianceStamped& msg) {
  const std::string& f = msg.header.frame_id;
  const std::string prefix = "place_";
  if (f.compare(0, prefix.size(), prefix) != 0) return;
  const int id = std::atoi(f.c_str() + prefix.size());
  by_stamp_[msg.header.stamp.toNSec()] = {id, poseOf(msg), laser_features::planarCovariance(msg.pose.covariance)};
  while (by_stamp_.size() > kKept) by_stamp_.erase(by_stamp_.begin());
  last_place_ = id;
  last_msg_ = msg;
}

bool LocalPoses::at(int place, const ros::Time& stamp, const Pose2D& odom_now,
                    const std::function<bool(const ros::Time&, Pose2D*)>& odom_at, Pose2D* pose,
                    Eigen::Matrix3d* cov) const {
  if (place < 0) return false;
  const auto it = by_stamp_.find(stamp.toNSec());
  if (it != by_stamp_.end() && it->second.place == place) {
    *pose = it->second.pose;
    *cov = it->second.cov;
    return true;
  }
  const ros::Time& last = last_msg_.header.stamp;
  if (last_place_ != place || std::abs((last - stamp).toSec()) >= kMaxAge) return false;
  Pose2D odom_then;
  if (!odom_at(last, &odom_then)) return false;
  *pose = laser_features::compose(poseOf(last_msg_), laser_features::compose(laser_features::inverse(odom_then), odom_now));
  *cov = Eigen::Matrix3d::Zero();
  return true;
}

}  // namespace exploration
