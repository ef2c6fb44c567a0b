#include "fingerprint/fingerprint.h"

#include <algorithm>
#include <cmath>

namespace fingerprint {
namespace {

Eigen::Vector2d inCamera(const Pose2& laser, const Eigen::Vector2d& p) {
  const double c = std::cos(laser.theta), s = std::sin(laser.theta);
  return {laser.x + c * p.x() - s * p.y(), laser.y + s * p.x() + c * p.y()};
}

}  // namespace

Feature laserCorner(const Pose2& laser_in_camera, const Eigen::Vector2d& xy, const Eigen::Matrix2d& cov,
                    double confidence) {
  const Eigen::Vector2d p = inCamera(laser_in_camera, xy);
  const double c = std::cos(laser_in_camera.theta), s = std::sin(laser_in_camera.theta);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  const Eigen::Matrix2d cov_camera = R * cov * R.transpose();
  const double r2 = std::max(p.squaredNorm(), 1e-12);
  const Eigen::Vector2d J(-p.y() / r2, p.x() / r2);
  Feature f;
  f.type = FeatureType::LaserCorner;
  f.bearing = std::atan2(p.y(), p.x());
  f.sigma = std::sqrt(std::max(0.0, J.dot(cov_camera * J)));
  f.strength = confidence;
  return f;
}

Feature laserOpening(const Pose2& laser_in_camera, const Eigen::Vector2d& xy, double width, bool door,
                     double confidence) {
  const Eigen::Vector2d p = inCamera(laser_in_camera, xy);
  const double r = std::max(p.norm(), 1e-6);
  Feature f;
  f.type = door ? FeatureType::LaserDoor : FeatureType::LaserJunction;
  f.bearing = std::atan2(p.y(), p.x());
  f.sigma = 2.0 * std::atan(0.5 * width / r) / std::sqrt(12.0);
  f.strength = confidence;
  return f;
}

void sortByBearing(std::vector<Feature>* features) {
  std::stable_sort(features->begin(), features->end(), [](const Feature& a, const Feature& b) {
    return a.bearing != b.bearing ? a.bearing < b.bearing : a.type < b.type;
  });
}

}  // namespace fingerprint
