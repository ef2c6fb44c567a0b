#include "hybrid_slam_rviz/hybrid_slam_panel.h"

#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>
#include <hybrid_slam_msgs/SaveMap.h>
#include <pluginlib/class_list_macros.hpp>
#include <std_srvs/SetBool.h>

#include "hybrid_slam_rviz/panel_model.h"

namespace hybrid_slam_rviz {

namespace {
// The stack's node names, as every launch file starts them (services under them).
const char* const kTopoSaveMap = "pomdp_topo/save_map";
const char* const kPlacesSaveMap = "ekf_local_map/save_map";
const char* const kPause = "exploration/pause";

std::string modeName(uint8_t mode) {
  using S = hybrid_slam_msgs::ExplorationStatus;
  switch (mode) {
    case S::TOPOLOGICAL: return "TOPOLOGICAL";
    case S::METRIC: return "METRIC";
    case S::SWITCHING: return "SWITCHING";
    case S::DONE: return "DONE";
    default: return "mode " + std::to_string(mode);
  }
}

QLabel* addRow(QGridLayout* grid, int row, const char* name) {
  grid->addWidget(new QLabel(name), row, 0, Qt::AlignTop);
  auto* value = new QLabel("-");
  value->setWordWrap(true);
  grid->addWidget(value, row, 1);
  return value;
}
}  // namespace

HybridSlamPanel::HybridSlamPanel(QWidget* parent) : rviz::Panel(parent) {
  auto* grid = new QGridLayout;
  mode_ = addRow(grid, 0, "Mode");
  where_ = addRow(grid, 1, "Where");
  belief_ = addRow(grid, 2, "Belief");
  map_ = addRow(grid, 3, "Map");
  travel_ = addRow(grid, 4, "Travel");
  save_ = new QPushButton("Save map");
  pause_ = new QPushButton("Pause exploration");
  auto* buttons = new QHBoxLayout;
  buttons->addWidget(save_);
  buttons->addWidget(pause_);
  result_ = new QLabel("");
  result_->setWordWrap(true);
  auto* layout = new QVBoxLayout;
  layout->addLayout(grid);
  layout->addLayout(buttons);
  layout->addWidget(result_);
  layout->addStretch();
  setLayout(layout);
  connect(save_, SIGNAL(clicked()), this, SLOT(saveMap()));
  connect(pause_, SIGNAL(clicked()), this, SLOT(togglePause()));
}

void HybridSlamPanel::onInitialize() {
  // rviz spins the global callback queue in its GUI thread: the callbacks may touch the widgets.
  status_sub_ = nh_.subscribe("exploration_status", 5, &HybridSlamPanel::onStatus, this);
  belief_sub_ = nh_.subscribe("topological_belief", 1, &HybridSlamPanel::onBelief, this);
}

void HybridSlamPanel::onStatus(const hybrid_slam_msgs::ExplorationStatus::ConstPtr& msg) {
  StatusFields s;
  s.mode = modeName(msg->mode);
  s.state = msg->state;
  s.place = msg->current_place;
  s.node = msg->current_node;
  s.places = msg->places;
  s.nodes = msg->nodes;
  s.explored = msg->openings_explored;
  s.unexplored = msg->openings_unexplored;
  s.travel_m = msg->travel_distance;
  s.real_time_factor = msg->real_time_factor;
  const StatusText t = describe(s);
  mode_->setText(QString::fromStdString(t.mode));
  where_->setText(QString::fromStdString(t.where));
  map_->setText(QString::fromStdString(t.map));
  travel_->setText(QString::fromStdString(t.travel));
  paused_ = msg->state.rfind("paused", 0) == 0;
  pause_->setText(paused_ ? "Resume exploration" : "Pause exploration");
}

void HybridSlamPanel::onBelief(const hybrid_slam_msgs::TopologicalBelief::ConstPtr& msg) {
  belief_->setText(QString::fromStdString(beliefText(msg->entropy, msg->entropy_max, msg->confident)));
}

template <class Srv>
bool HybridSlamPanel::call(const std::string& name, Srv* srv, std::string* message) {
  const std::string resolved = nh_.resolveName(name);
  if (!ros::service::exists(resolved, false)) {
    *message = resolved + " is not running";
    return false;
  }
  if (!ros::service::call(resolved, *srv)) {
    *message = resolved + " failed";
    return false;
  }
  *message = srv->response.message;
  return srv->response.success;
}

void HybridSlamPanel::saveMap() {
  std::string text;
  for (const char* name : {kTopoSaveMap, kPlacesSaveMap}) {
    hybrid_slam_msgs::SaveMap srv;  // an empty path: each node's own map_file
    std::string message;
    const bool ok = call(name, &srv, &message);
    text += std::string(ok ? "" : "NOT saved: ") + message + "\n";
  }
  result_->setText(QString::fromStdString(text));
}

void HybridSlamPanel::togglePause() {
  std_srvs::SetBool srv;
  srv.request.data = !paused_;
  std::string message;
  if (call(kPause, &srv, &message) || message.rfind("already", 0) == 0 || message.rfind("not paused", 0) == 0)
    paused_ = srv.request.data;
  pause_->setText(paused_ ? "Resume exploration" : "Pause exploration");
  result_->setText(QString::fromStdString(message));
}

}  // namespace hybrid_slam_rviz

PLUGINLIB_EXPORT_CLASS(hybrid_slam_rviz::HybridSlamPanel, rviz::Panel)
