// The one place where bullet_sim's core types become ROS messages.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <tf2/LinearMath/Transform.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/LaserScan.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "bullet_sim/panoramic_camera.h"
#include "bullet_sim/simulator.h"

namespace bullet_sim {

tf2::Transform toTf(const Pose2& pose);
geometry_msgs::TransformStamped toTransform(const tf2::Transform& t, const ros::Time& stamp, const std::string& parent,
                                            const std::string& child);

// Odometry as the robot's encoders report it (pose, covariance and twist), odom -> base.
nav_msgs::Odometry toOdometry(const Simulator& sim, const ros::Time& stamp, const std::string& odom_frame,
                              const std::string& base_frame);

// The true pose and twist in the world frame (evaluation only).
nav_msgs::Odometry toGroundTruth(const Simulator& sim, const ros::Time& stamp, const std::string& world_frame,
                                 const std::string& base_frame);

// Fills `msg` (kept between calls so that ranges are not reallocated) with a scan.
void toLaserScan(const Simulator& sim, const std::vector<float>& ranges, const ros::Time& stamp, double scan_period,
                 const std::string& frame, sensor_msgs::LaserScan* msg);

// The panoramic camera's image (rgb8; `msg` keeps its buffer between calls) and its camera_info: the
// image is equirectangular, which no distortion model of camera_info describes: K holds the pixels per
// radian (fx around, fy up and down) and the centre pixel (the horizon ahead); D is empty.
void toImage(const std::vector<uint8_t>& rgb, const CameraParams& params, const ros::Time& stamp,
             const std::string& frame, sensor_msgs::Image* msg);
sensor_msgs::CameraInfo toCameraInfo(const CameraParams& params, const ros::Time& stamp, const std::string& frame);

// Walls, furniture, pillars, and the ground-truth regions and doors, for rviz.
visualization_msgs::MarkerArray worldMarkers(const World& world, const std::string& frame);

}  // namespace bullet_sim
