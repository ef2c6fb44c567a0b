#include "ros_conversions.h"


#include <cmath>

#include "bullet_sim/ray_caster.h"

namespace bullet_sim {
namespace {

geometry_msgs::Quaternion yawToQuaternion(double yaw) {
  geometry_msgs::Quaternion q;
  q.z = std::sin(yaw / 2);
  q.w = std::cos(yaw / 2);
  return q;
}

std_msgs::ColorRGBA rgba(float r, float g, float b, float a) {
  std_msgs::ColorRGBA c;
  c.r = r;
  c.g = g;
  c.b = b;
  c.a = a;
  return c;
}

geometry_msgs::Point point(double x, double y, double z = 0.0) {
  geometry_msgs::Point p;
  p.x = x;
  p.y = y;
  p.z = z;
  return p;
}

}  // namespace

tf2::Transform toTf(const Pose2& pose) {
  tf2::Quaternion q;
  q.setRPY(0.0, 0.0, pose.yaw);
  return tf2::Transform(q, tf2::Vector3(pose.x, pose.y, 0.0));
}

geometry_msgs::TransformStamped toTransform(const tf2::Transform& t, const ros::Time& stamp, const std::string& parent,
                                            const std::string& child) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = stamp;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = t.getOrigin().x();
  m.transform.translation.y = t.getOrigin().y();
  m.transform.translation.z = t.getOrigin().z();
  m.transform.rotation.x = t.getRotation().x();
  m.transform.rotation.y = t.getRotation().y();
  m.transform.rotation.z = t.getRotation().z();
  m.transform.rotation.w = t.getRotation().w();
  return m;
}

nav_msgs::Odometry toOdometry(const Simulator& sim, const ros::Time& stamp, const std::string& odom_frame,
                              const std::string& base_frame) {
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = odom_frame;
  m.child_frame_id = base_frame;
  const Pose2& p = sim.odomPose();
  m.pose.pose.position.x = p.x;
  m.pose.pose.position.y = p.y;
  m.pose.pose.orientation = yawToQuaternion(p.yaw);
  // 6x6 row-major over (x, y, z, roll, pitch, yaw); the planar part from the wheel noise model.
  const Eigen::Matrix3d& c = sim.odomCovariance();
  const int idx[3] = {0, 1, 5};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.pose.covariance[idx[i] * 6 + idx[j]] = c(i, j);
  m.pose.covariance[2 * 6 + 2] = m.pose.covariance[3 * 6 + 3] = m.pose.covariance[4 * 6 + 4] = 1e6;
  m.twist.twist.linear.x = sim.odomLinearVelocity();
  m.twist.twist.angular.z = sim.odomAngularVelocity();
  return m;
}

nav_msgs::Odometry toGroundTruth(const Simulator& sim, const ros::Time& stamp, const std::string& world_frame,
                                 const std::string& base_frame) {
  nav_msgs::Odometry m;
  m.header.stamp = stamp;
  m.header.frame_id = world_frame;
  m.child_frame_id = base_frame;
  const Pose2& p = sim.truePose();
  m.pose.pose.position.x = p.x;
  m.pose.pose.position.y = p.y;
  m.pose.pose.orientation = yawToQuaternion(p.yaw);
  m.twist.twist.linear.x = sim.trueLinearVelocity();
  m.twist.twist.angular.z = sim.trueAngularVelocity();
  return m;
}

void toLaserScan(const Simulator& sim, const std::vector<float>& ranges, const ros::Time& stamp, double scan_period,
                 const std::string& frame, sensor_msgs::LaserScan* msg) {
  const LaserGeometry& g = sim.laser();
  msg->header.stamp = stamp;
  msg->header.frame_id = frame;
  msg->angle_min = static_cast<float>(g.angle_min);
  msg->angle_max = static_cast<float>(g.angle_max());
  msg->angle_increment = static_cast<float>(g.angle_increment);
  msg->time_increment = 0.0f;  // every beam of a scan is cast at the scan's instant
  msg->scan_time = static_cast<float>(scan_period);
  msg->range_min = static_cast<float>(sim.params().laser_range_min);
  msg->range_max = static_cast<float>(sim.params().laser_range_max);
  msg->ranges.assign(ranges.begin(), ranges.end());
}

void toImage(const std::vector<uint8_t>& rgb, const CameraParams& params, const ros::Time& stamp,
             const std::string& frame, sensor_msgs::Image* msg) {
  msg->header.stamp = stamp;
  msg->header.frame_id = frame;
  msg->width = uint32_t(params.width);
  msg->height = uint32_t(params.height);
  msg->encoding = "rgb8";
  msg->is_bigendian = 0;
  msg->step = uint32_t(params.width) * 3;
  msg->data = rgb;
}

sensor_msgs::CameraInfo toCameraInfo(const CameraParams& params, const ros::Time& stamp, const std::string& frame) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame;
  info.width = uint32_t(params.width);
  info.height = uint32_t(params.height);
  info.distortion_model = "";  // equirectangular (PanoramicCamera::columnBearing, rowElevation)
  const double fx = params.width / (2.0 * M_PI), fy = params.height / params.vertical_fov;
  info.K = {fx, 0.0, 0.5 * params.width, 0.0, fy, 0.5 * params.height, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {fx, 0.0, 0.5 * params.width, 0.0, 0.0, fy, 0.5 * params.height, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

visualization_msgs::MarkerArray worldMarkers(const World& world, const std::string& frame) {
  visualization_msgs::MarkerArray out;
  int id = 0;
  auto base = [&](const std::string& ns, int type) {
    visualization_msgs::Marker m;
    m.header.frame_id = frame;
    m.ns = ns;
    m.id = id++;
    m.type = type;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.orientation.w = 1.0;
    return m;
  };
  std::vector<SolidSource> sources;
  const auto boxes = world.solidBoxes(&sources);
  auto rgbaOf = [](const std::optional<Rgb>& c, std_msgs::ColorRGBA fallback) {
    return c ? rgba(c->r / 255.0f, c->g / 255.0f, c->b / 255.0f, 1.0f) : fallback;
  };
  for (size_t i = 0; i < boxes.size(); ++i) {
    const bool furniture = sources[i].kind == SolidSource::Box;
    const OrientedBox& b = boxes[i];
    auto m = base(furniture ? "furniture" : "walls", visualization_msgs::Marker::CUBE);
    m.pose.position = point(b.center.x, b.center.y, b.height / 2);
    m.pose.orientation = yawToQuaternion(b.yaw);
    m.scale.x = 2 * b.half_x;
    m.scale.y = 2 * b.half_y;
    m.scale.z = b.height;
    m.color = rgbaOf(b.color, furniture ? rgba(0.65f, 0.45f, 0.25f, 1.0f) : rgba(0.75f, 0.75f, 0.78f, 1.0f));
    out.markers.push_back(m);
  }
  for (const Cylinder& c : world.cylinders) {
    auto m = base("pillars", visualization_msgs::Marker::CYLINDER);
    m.pose.position = point(c.center.x, c.center.y, c.height / 2);
    m.scale.x = m.scale.y = 2 * c.radius;
    m.scale.z = c.height;
    m.color = rgbaOf(c.color, rgba(0.5f, 0.5f, 0.55f, 1.0f));
    out.markers.push_back(m);
  }
  for (const Region& r : world.regions) {
    auto outline = base("regions", visualization_msgs::Marker::LINE_STRIP);
    outline.scale.x = 0.03;
    outline.color = r.hallway ? rgba(0.2f, 0.4f, 1.0f, 0.6f) : rgba(0.2f, 0.8f, 0.3f, 0.6f);
    for (const Vec2& p : r.polygon) outline.points.push_back(point(p.x, p.y, 0.01));
    outline.points.push_back(outline.points.front());
    out.markers.push_back(outline);
    double cx = 0, cy = 0;
    for (const Vec2& p : r.polygon) {
      cx += p.x / r.polygon.size();
      cy += p.y / r.polygon.size();
    }
    auto label = base("region_names", visualization_msgs::Marker::TEXT_VIEW_FACING);
    label.pose.position = point(cx, cy, 0.5);
    label.scale.z = 0.4;
    label.color = rgba(1.0f, 1.0f, 1.0f, 0.9f);
    label.text = r.name;
    out.markers.push_back(label);
  }
  // A door is drawn as a flat bar across its opening: the wall runs along the axis on which the
  // opening's edges are nearest.
  const RayCaster2D caster(world);
  for (const Door& d : world.doors) {
    auto m = base("doors", visualization_msgs::Marker::CUBE);
    const double along_x = caster.cast(d.center.x, d.center.y, 1, 0, 50) + caster.cast(d.center.x, d.center.y, -1, 0, 50);
    const double along_y = caster.cast(d.center.x, d.center.y, 0, 1, 50) + caster.cast(d.center.x, d.center.y, 0, -1, 50);
    m.pose.position = point(d.center.x, d.center.y, 0.02);
    m.pose.orientation = yawToQuaternion(along_x <= along_y ? 0.0 : M_PI / 2);
    m.scale.x = d.width;
    m.scale.y = 0.15;
    m.scale.z = 0.04;
    m.color = rgba(1.0f, 0.6f, 0.0f, 0.9f);
    out.markers.push_back(m);
  }
  return out;
}

}  // namespace bullet_sim
