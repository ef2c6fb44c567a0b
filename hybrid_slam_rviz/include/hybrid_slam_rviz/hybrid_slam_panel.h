// rviz panel: what the exploration is doing (mode and state, current place and node, the belief's
// entropy against U_max, places, nodes, openings, travel), live from `exploration_status` and
// `topological_belief`; buttons that save the map (pomdp_topo's and ekf_local_map's save_map) and
// pause or resume the exploration (exploration's ~pause).
#pragma once

#ifndef Q_MOC_RUN
#include <hybrid_slam_msgs/ExplorationStatus.h>
#include <hybrid_slam_msgs/TopologicalBelief.h>
#include <ros/ros.h>
#include <rviz/panel.h>
#endif

class QLabel;
class QPushButton;

namespace hybrid_slam_rviz {

class HybridSlamPanel : public rviz::Panel {
  Q_OBJECT
 public:
  explicit HybridSlamPanel(QWidget* parent = nullptr);
  void onInitialize() override;

 private Q_SLOTS:
  void saveMap();
  void togglePause();

 private:
  void onStatus(const hybrid_slam_msgs::ExplorationStatus::ConstPtr& msg);
  void onBelief(const hybrid_slam_msgs::TopologicalBelief::ConstPtr& msg);
  /// Calls a service by name; false (with the reason in *message) when it is not there or fails.
  template <class Srv>
  bool call(const std::string& name, Srv* srv, std::string* message);

  ros::NodeHandle nh_;
  ros::Subscriber status_sub_, belief_sub_;
  QLabel *mode_ = nullptr, *where_ = nullptr, *belief_ = nullptr, *map_ = nullptr, *travel_ = nullptr,
         *result_ = nullptr;
  QPushButton *save_ = nullptr, *pause_ = nullptr;
  bool paused_ = false;
};

}  // namespace hybrid_slam_rviz
