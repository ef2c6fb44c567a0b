#include "bullet_sim/robot_model.h"

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>

namespace bullet_sim {

namespace {

struct PlanarPose {
  double x = 0.0, y = 0.0, z = 0.0, yaw = 0.0;
};

// The pose of `link` in `base_link`, composed along the fixed joints up to it (a planar robot: x, y,
// z, yaw).
PlanarPose fixedChainPose(const urdf::ModelInterface& model, const std::string& base_link, const std::string& link_name) {
  PlanarPose out;
  urdf::LinkConstSharedPtr link = model.getLink(link_name);
  if (!link) throw RobotModelError("robot_description: no link '" + link_name + "'");
  while (link->name != base_link) {
    const urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint) throw RobotModelError("robot_description: link '" + link_name + "' is not below '" + base_link + "'");
    if (joint->type != urdf::Joint::FIXED)
      throw RobotModelError("robot_description: joint '" + joint->name + "' between base and " + link_name +
                            " must be fixed");
    const urdf::Pose& p = joint->parent_to_joint_origin_transform;
    double roll, pitch, jyaw;
    p.rotation.getRPY(roll, pitch, jyaw);
    // child pose in parent: p (+) (x, y, yaw)
    const double c = std::cos(jyaw), s = std::sin(jyaw);
    const double nx = p.position.x + c * out.x - s * out.y;
    const double ny = p.position.y + s * out.x + c * out.y;
    out.x = nx;
    out.y = ny;
    out.z += p.position.z;
    out.yaw += jyaw;
    link = model.getLink(joint->parent_link_name);
    if (!link) throw RobotModelError("robot_description: missing link '" + joint->parent_link_name + "'");
  }
  out.yaw = std::atan2(std::sin(out.yaw), std::cos(out.yaw));
  return out;
}

}  // namespace

RobotModel robotModelFromUrdf(const std::string& urdf_xml, const std::string& base_link, const std::string& laser_link,
                              const std::string& camera_link) {
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

  const PlanarPose laser = fixedChainPose(*model, base_link, laser_link);
  out.laser_x = laser.x;
  out.laser_y = laser.y;
  out.laser_z = laser.z;
  out.laser_yaw = laser.yaw;
  if (!camera_link.empty()) {
    const PlanarPose camera = fixedChainPose(*model, base_link, camera_link);
    out.has_camera = true;
    out.camera_x = camera.x;
    out.camera_y = camera.y;
    out.camera_z = camera.z;
    out.camera_yaw = camera.yaw;
    out.camera_frame = camera_link;
  }
  return out;
}

}  // namespace bullet_sim
