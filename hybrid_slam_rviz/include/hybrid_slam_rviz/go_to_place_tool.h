// rviz tool: click and drag a pose (as with "2D Nav Goal"); it is sent as a GoToPlace mission to
// `go_to_place` in the frame of the place whose origin is nearest the click (or of the place the
// tool's "Place" property names), from ekf_local_map's place frames on tf.
#pragma once

#ifndef Q_MOC_RUN
#include <actionlib/client/simple_action_client.h>
#include <hybrid_slam_msgs/GoToPlaceAction.h>
#include <rviz/default_plugin/tools/pose_tool.h>

#include <memory>
#endif

namespace rviz {
class IntProperty;
class StringProperty;
}  // namespace rviz

namespace hybrid_slam_rviz {

class GoToPlaceTool : public rviz::PoseTool {
  Q_OBJECT
 public:
  GoToPlaceTool();
  void onInitialize() override;

 protected:
  void onPoseSet(double x, double y, double theta) override;

 private:
  using Client = actionlib::SimpleActionClient<hybrid_slam_msgs::GoToPlaceAction>;
  rviz::IntProperty* place_ = nullptr;
  rviz::StringProperty* prefix_ = nullptr;
  std::unique_ptr<Client> client_;
};

}  // namespace hybrid_slam_rviz
