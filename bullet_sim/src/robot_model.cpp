#include "bullet_sim/robot_model.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>

namespace bullet_sim {

RobotModel robotModelFromUrdf(const std::string& urdf_xml, const std::string& base_link, const std::string& laser_link) {
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_xml);
  if (!model) throw RobotModelError("robot_description: not a valid URDF");
  RobotModel out;
  out.base_frame = base_link;
  out.laser_frame = laser_link;

  const urdf::LinkConstSharedPtr base = model->getLink(base_link);
  if (!base) throw RobotModelError("robot_description: no link '" + base_link + "'");
  if (!base->collision || !base->collision->geometry || base->collision->geometry->type != urdf::Geometry::CYLINDER)
    throw RobotModelError("robot_description: link '" + base_link + "' needs a cylinder collision (the footprint)");
  out.radius = std::static_pointer_cast<urdf::Cylinder>(base->collision->geometry)->radius;
  if (!(out.radius > 0.0)) throw RobotModelError("robot_description: footprint radius must be positive");

  // Compose the fixed joints from the laser link up to the base link (planar robot: x, y, z, yaw).
  double x = 0.0, y = 0.0, z = 0.0, yaw = 0.0;
  urdf::LinkConstSharedPtr link = model->getLink(laser_link);
  if (!link) throw RobotModelError("robot_description: no link '" + laser_link + "'");
  while (link->name != base_link) {
    const urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint) throw RobotModelError("robot_description: link '" + laser_link + "' is not below '" + base_link + "'");
    if (joint->type != urdf::Joint::FIXED)
      throw RobotModelError("robot_description: joint '" + joint->name + "' between base and laser must be fixed");
    const urdf::Pose& p = joint->parent_to_joint_origin_transform;
    double roll, pitch, jyaw;
    p.rotation.getRPY(roll, pitch, jyaw);
    // child pose in parent: p ⊕ (x, y, yaw)
    const double c = std::cos(jyaw), s = std::sin(jyaw);
    const double nx = p.position.x + c * x - s * y;
    const double ny = p.position.y + s * x + c * y;
    x = nx;
    y = ny;
    z += p.position.z;
    yaw += jyaw;
    link = model->getLink(joint->parent_link_name);
    if (!link) throw RobotModelError("robot_description: missing link '" + joint->parent_link_name + "'");
  }
  out.laser_x = x;
  out.laser_y = y;
  out.laser_z = z;
  out.laser_yaw = std::atan2(std::sin(yaw), std::cos(yaw));
  return out;
}

}  // namespace bullet_sim
