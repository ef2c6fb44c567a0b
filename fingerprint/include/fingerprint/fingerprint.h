// A fingerprint of place (Tapus & Siegwart): the circular list of the features around the robot -
// the camera's vertical edges and colour patches, the laser's corners and openings - ordered by
// bearing in the camera's frame. The laser's features come in the laser's frame; their bearing is
// taken from the camera's position (the two are a few centimetres apart on the robot).
//
// ROS-free: Eigen and the standard library.
#pragma once

#include "fingerprint/visual_features.h"

#include <Eigen/Core>

#include <vector>

namespace fingerprint {

/// A planar pose (m, m, rad): the laser's in the camera's frame.
struct Pose2 {
  double x = 0.0, y = 0.0, theta = 0.0;
};

/// A laser corner at (x, y) in the laser frame with its 2x2 position covariance: its bearing from
/// the camera, and the bearing's deviation propagated from the covariance (d bearing / d (x, y) =
/// (-y, x) / r^2, in the camera frame).
Feature laserCorner(const Pose2& laser_in_camera, const Eigen::Vector2d& xy, const Eigen::Matrix2d& cov,
                    double confidence);
/// A laser opening of `width` (m) centred at `xy` (laser frame): a door or a junction. The camera
/// sees it as the angle its width subtends; its centre is anywhere over it (uniform).
Feature laserOpening(const Pose2& laser_in_camera, const Eigen::Vector2d& xy, double width, bool door,
                     double confidence);
/// Orders `features` by bearing, from -pi to pi (ties: by type): the circular list.
void sortByBearing(std::vector<Feature>* features);

}  // namespace fingerprint
