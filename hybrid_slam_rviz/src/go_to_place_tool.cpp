#include "hybrid_slam_rviz/go_to_place_tool.h"

#include <algorithm>

#include <pluginlib/class_list_macros.hpp>
#include <rviz/display_context.h>
#include <rviz/ogre_helpers/arrow.h>
#include <rviz/frame_manager.h>
#include <rviz/properties/int_property.h>
#include <rviz/properties/string_property.h>
#include <tf2/utils.h>
#include <tf2_ros/buffer.h>

#include "hybrid_slam_rviz/panel_model.h"

namespace hybrid_slam_rviz {

GoToPlaceTool::GoToPlaceTool() {
  shortcut_key_ = 'p';
}

void GoToPlaceTool::onInitialize() {
  PoseTool::onInitialize();
  arrow_->setColor(0.9f, 0.4f, 0.1f, 1.0f);
  setName("Go to place");
  place_ = new rviz::IntProperty("Place", -1, "The place the goal is in; -1: the place whose origin is nearest the click.",
                                 getPropertyContainer());
  place_->setMin(-1);
  prefix_ = new rviz::StringProperty("Place frame prefix", "place_",
                                     "ekf_local_map's place frames are <prefix><id> (its place_frame_prefix).",
                                     getPropertyContainer());
  client_ = std::make_unique<Client>("go_to_place", true);
}

void GoToPlaceTool::onPoseSet(double x, double y, double theta) {
  const std::string fixed = context_->getFixedFrame().toStdString();
  const auto buffer = context_->getFrameManager()->getTF2BufferPtr();
  std::vector<PlaceFrame> places;
  std::vector<std::string> frames;
  buffer->_getFrameStrings(frames);
  for (const std::string& frame : frames) {
    const auto id = placeOfFrame(frame, prefix_->getStdString());
    if (!id) continue;
    try {
      const auto t = buffer->lookupTransform(fixed, frame, ros::Time(0));
      places.push_back({*id, {t.transform.translation.x, t.transform.translation.y, tf2::getYaw(t.transform.rotation)}});
    } catch (const tf2::TransformException&) {
    }
  }
  const int wanted = place_->getInt();
  const int id = wanted >= 0 ? wanted : nearestPlace(places, x, y);
  const auto place = std::find_if(places.begin(), places.end(), [id](const PlaceFrame& p) { return p.id == id; });
  if (place == places.end()) {
    setStatus(id < 0 ? "No place frames on tf yet (ekf_local_map makes them)" : QString("No frame for place %1").arg(id));
    ROS_WARN("GoToPlace tool: %s", id < 0 ? "no place frames on tf" : ("no frame for place " + std::to_string(id)).c_str());
    return;
  }
  if (!client_->isServerConnected()) {
    setStatus("No GoToPlace server on go_to_place (explore.launch serve_missions:=true, or missions.launch)");
    ROS_WARN("GoToPlace tool: no action server on go_to_place");
    return;
  }
  const Pose2D g = goalInPlace(place->pose, {x, y, theta});
  hybrid_slam_msgs::GoToPlaceGoal goal;
  goal.place_id = id;
  goal.goal.x = g.x;
  goal.goal.y = g.y;
  goal.goal.theta = g.theta;
  client_->sendGoal(goal, [id](const actionlib::SimpleClientGoalState& state,
                               const hybrid_slam_msgs::GoToPlaceResultConstPtr& r) {
    ROS_INFO("GoToPlace tool: mission to place %d ended %s: %s", id, state.toString().c_str(), r ? r->message.c_str() : "");
  });
  ROS_INFO("GoToPlace tool: mission to place %d, (%.2f, %.2f, %.2f) in its frame", id, g.x, g.y, g.theta);
  setStatus(QString("Sent: place %1, (%2, %3) m in its frame").arg(id).arg(g.x, 0, 'f', 2).arg(g.y, 0, 'f', 2));
}

}  // namespace hybrid_slam_rviz

PLUGINLIB_EXPORT_CLASS(hybrid_slam_rviz::GoToPlaceTool, rviz::Tool)
