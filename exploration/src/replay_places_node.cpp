// replay_places_node: the places of a replayed bag (launch/replay.launch). Nobody steers the robot,
// so this passive node stands in for the coordinator's bookkeeping: PassivePlaces decides from the
// scans' place type and the topological belief when the robot enters and leaves a room; the node
// creates, re-enters (relocate_at_door) and closes places in ekf_local_map, links each door node to
// its place in pomdp_topo, pauses the topological map while in a room (exploration_status METRIC,
// as the coordinator does), and when the bag has ended saves both maps, writes a summary and shuts
// down (it is the launch's required node).
// With ~bag_check/mode features_only (the bag has no odometry) it builds nothing and only waits
// for the bag's end.
#include <geometry_msgs/TransformStamped.h>
#include <hybrid_slam_msgs/AddDoor.h>
#include <hybrid_slam_msgs/CreatePlace.h>
#include <hybrid_slam_msgs/ExplorationStatus.h>
#include <hybrid_slam_msgs/LaserFeatures.h>
#include <hybrid_slam_msgs/LocalMap.h>
#include <hybrid_slam_msgs/OpeningFeature.h>
#include <hybrid_slam_msgs/RelocateAtDoor.h>
#include <hybrid_slam_msgs/RelocationResult.h>
#include <hybrid_slam_msgs/SaveMap.h>
#include <hybrid_slam_msgs/TopologicalBelief.h>
#include <hybrid_slam_msgs/TopologicalMap.h>
#include <hybrid_slam_msgs/TopologicalState.h>
#include <hybrid_slam_msgs/UpdateOpening.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tf2/utils.h>
#include <tf2_ros/transform_listener.h>

#include <chrono>
#include <fstream>
#include <map>
#include <set>

#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "laser_features/node_main_ros.h"
#include "exploration/door_crossings.h"
#include "exploration/passive_places.h"
#include "ros_conversions.h"
#include "service_call.h"

namespace exploration {
namespace {

ScanPlace toScanPlace(uint8_t type) {
  if (type == hybrid_slam_msgs::LaserFeatures::ROOM) return ScanPlace::Room;
  if (type == hybrid_slam_msgs::LaserFeatures::HALLWAY) return ScanPlace::Hallway;
  return ScanPlace::Unknown;
}

class ReplayPlacesNode {
 public:
  ReplayPlacesNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), tf_listener_(tf_buffer_) {
    visitPassivePlacesParams(&params_, laser_features::RosParamReader{pnh});
    std::string why;
    if (!PassivePlaces::validate(params_, &why)) throw std::runtime_error("bad parameter: " + why);
    places_ = PassivePlaces(params_);
    visitDoorCrossingsParams(&crossing_params_, laser_features::RosParamReader{pnh});
    if (!DoorCrossings::validate(crossing_params_, &why)) throw std::runtime_error("bad parameter: " + why);
    crossings_ = DoorCrossings(crossing_params_);
    pnh.param<std::string>("topo_node", topo_node_, "pomdp_topo");
    pnh.param<std::string>("local_map_node", local_map_node_, "ekf_local_map");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param("mapping", mapping_, true);
    pnh.param("bag_end_time", bag_end_time_, 0.0);
    pnh.param("end_tolerance", end_tolerance_, 1.0);
    pnh.param("end_grace", end_grace_, 2.0);
    pnh.param("end_idle_timeout", end_idle_timeout_, 10.0);
    pnh.param("service_timeout", service_timeout_, 5.0);
    pnh.param<std::string>("summary_file", summary_file_, "");
    // What scripts/check_bag found in the bag (replay.launch puts its answer under ~bag_check).
    std::string mode;
    pnh.param<std::string>("bag_check/mode", mode, "full");
    pnh.param("bag_check/end_time", bag_end_time_, bag_end_time_);
    pnh.param("bag_check/duration", bag_duration_, 0.0);
    if (mode == "features_only") mapping_ = false;

    status_pub_ = nh_.advertise<hybrid_slam_msgs::ExplorationStatus>("exploration_status", 10, true);
    features_sub_ = nh_.subscribe("features", 50, &ReplayPlacesNode::onFeatures, this);
    if (mapping_) {
      map_sub_ = nh_.subscribe("topological_map", 2, &ReplayPlacesNode::onMap, this);
      belief_sub_ = nh_.subscribe("topological_belief", 20, &ReplayPlacesNode::onBelief, this);
      state_sub_ = nh_.subscribe("topological_state", 20, &ReplayPlacesNode::onTopoState, this);
      local_map_sub_ = nh_.subscribe("local_map", 5, &ReplayPlacesNode::onLocalMap, this);
      relocation_sub_ = nh_.subscribe("relocation", 10, &ReplayPlacesNode::onRelocation, this);
      map_odom_sub_ = nh_.subscribe("map_odom", 10, &ReplayPlacesNode::onMapOdom, this);
    } else {
      ROS_WARN("replay_places: the bag has no odometry (no odom topic, no tf %s -> %s): only laser_features runs; "
               "no topological map and no places are built", odom_frame_.c_str(), base_frame_.c_str());
    }
    end_timer_ = nh_.createWallTimer(ros::WallDuration(0.2), &ReplayPlacesNode::onEndTimer, this);
    wall_start_ = ros::WallTime::now();
    last_clock_wall_ = wall_start_;
  }

 private:
  // --- inputs ---------------------------------------------------------------------------------
  void onMap(const hybrid_slam_msgs::TopologicalMap& msg) {
    nodes_ = msg.nodes.size();
    edges_ = msg.edges.size();
    door_nodes_.clear();
    for (const auto& n : msg.nodes) {
      if (n.type == hybrid_slam_msgs::TopoNode::DOOR) door_nodes_.insert(int(n.id));
      // A door linked to a place (by this run, or a link the map builder carried over a merge).
      for (const auto& o : n.openings) {
        if (o.place_id >= 0) places_.linkDoor(int(n.id), o.place_id);
      }
    }
  }

  void onBelief(const hybrid_slam_msgs::TopologicalBelief& msg) {
    door_node_ = -1;
    const int ml = msg.most_likely;
    if (!msg.confident || ml < 0 || size_t(ml) >= msg.at_node.size() || size_t(ml) >= msg.state_edge.size()) return;
    if (msg.at_node[ml] && door_nodes_.count(int(msg.state_edge[ml]))) door_node_ = int(msg.state_edge[ml]);
  }

  void onTopoState(const hybrid_slam_msgs::TopologicalState& msg) { heading_map_ = msg.heading; }

  // ekf_local_map's map -> odom (its topic: publish_tf is off in a replay).
  void onMapOdom(const geometry_msgs::TransformStamped& msg) {
    map_odom_ = Pose2D{msg.transform.translation.x, msg.transform.translation.y, tf2::getYaw(msg.transform.rotation)};
  }

  void onLocalMap(const hybrid_slam_msgs::LocalMap& msg) { lines_per_place_[msg.place_id] = msg.lines.size(); }

  void onRelocation(const hybrid_slam_msgs::RelocationResult& msg) {
    if (msg.success) ++relocations_ok_;
    else ++relocations_failed_;
    if (msg.place_id != awaiting_verdict_) return;
    if (!msg.success && places_.travel() - reentry_travel_ < params_.relocation_distance) return;  // not yet
    awaiting_verdict_ = -1;
    if (msg.success || finished_) return;
    // The place behind this door did not match the scans (a look-alike door, odometry's drift): the
    // robot is in a room not mapped yet.
    Pose2D odom;
    if (!lookupOdom(msg.header.stamp, &odom)) return;
    const PlaceAction a = places_.reentryRefused(odom);
    if (a.kind != PlaceAction::Enter) return;
    decision_stamp_ = msg.header.stamp;
    ROS_WARN("replay_places: place %d not recognized behind door %d (%s): a new place instead", msg.place_id,
             a.door_id, msg.verdict.c_str());
    ++reentries_refused_;
    --reentries_;
    leave();
    enter(a);
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeatures& msg) {
    ++features_;
    if (!mapping_ || finished_) return;
    PlaceObservation o;
    if (!lookupOdom(msg.header.stamp, &o.odom)) return;
    o.type = toScanPlace(msg.place_type);
    o.confidence = msg.place_type_confidence;
    o.door_node = door_node_;
    o.heading_map = heading_map_;
    o.map_odom = map_odom_;
    // The features are in the scan's frame: the doors go to the robot's (a scanner off its centre).
    Pose2D sensor;
    std::string why;
    if (!laser_features::lookupPose2D(tf_buffer_, base_frame_, msg.header.frame_id, msg.header.stamp, 0.1, &sensor, &why)) {
      ROS_WARN_THROTTLE(10.0, "replay_places: no transform %s -> %s: %s", base_frame_.c_str(), msg.header.frame_id.c_str(),
                        why.c_str());
      return;
    }
    std::vector<DoorSighting> doors;
    for (const auto& op : msg.openings) {
      if (op.kind != hybrid_slam_msgs::OpeningFeature::DOOR) continue;
      doors.push_back(inRobotFrame(sensor, {op.left.x, op.left.y, op.right.x, op.right.y}));
    }
    o.crossing = crossings_.update(o.odom, doors);
    if (o.crossing) ++crossings_seen_;
    const PlaceAction a = places_.update(o);
    decision_stamp_ = msg.header.stamp;
    if (a.kind == PlaceAction::Enter && a.leave_first) leave();
    if (a.kind == PlaceAction::Enter) enter(a);
    if (a.kind == PlaceAction::Leave) leave();
    if (places_.inPlace() != last_in_place_ || (msg.header.stamp - last_status_).toSec() >= 1.0)
      publishStatus(msg.header.stamp);
  }

  bool lookupOdom(const ros::Time& stamp, Pose2D* out) {
    std::string why;
    if (laser_features::lookupPose2D(tf_buffer_, odom_frame_, base_frame_, stamp, 0.1, out, &why)) return true;
    ROS_WARN_THROTTLE(10.0, "replay_places: no odometry (%s -> %s) at a scan's time: %s", odom_frame_.c_str(),
                      base_frame_.c_str(), why.c_str());
    return false;
  }

  // --- places -----------------------------------------------------------------------------------
  template <typename Srv>
  bool call(const std::string& name, Srv* srv) {
    return callService(nh_, "replay_places", name, srv, service_timeout_);
  }

  void enter(const PlaceAction& a) {
    if (a.known_place >= 0 && relocate(a)) {
      places_.entered(a.known_place, a.door_id);
      awaiting_verdict_ = a.known_place;
      reentry_travel_ = places_.travel();
      ++reentries_;
      ROS_INFO("replay_places: back in place %d through door %d%s", a.known_place, a.door_id,
               a.door_node >= 0 ? " (a door node)" : " (crossed by the path)");
      return;
    }
    hybrid_slam_msgs::CreatePlace create;
    create.request.use_display_pose = false;
    if (!call(local_map_node_ + "/create_place", &create) || !create.response.success) {
      places_.entered(-1, -1);
      return;
    }
    const int id = create.response.place_id;
    places_.entered(id, a.door_id);
    ++created_;
    ROS_INFO("replay_places: room entered: place %d created%s", id,
             a.door_node >= 0 ? (" behind door node " + std::to_string(a.door_node)).c_str()
                              : a.door_id >= 0 ? (" behind crossed door " + std::to_string(a.door_id)).c_str()
                                               : " (no door node passed)");
    // The place's origin is the robot at its latest odometry (origin_stamp), not at the scan that
    // decided: a robot turning into the door has turned on meanwhile. The door goes in that frame.
    PlaceAction at_origin = a;
    Pose2D origin;
    if (lookupOdom(create.response.origin_stamp, &origin)) {
      at_origin.door_in_robot = laser_features::compose(laser_features::inverse(origin), a.door_odom);
      at_origin.door_in_robot.theta = laser_features::normalizeAngle(at_origin.door_in_robot.theta);
    }
    if (a.door_id >= 0) storeDoor(at_origin, id);
    if (a.door_node >= 0) linkDoor(at_origin, id);
  }

  bool relocate(const PlaceAction& a) {
    hybrid_slam_msgs::RelocateAtDoor srv;
    srv.request = relocateRequest(a.known_place, a.door_id, a.robot_from_door, params_.relocation_sigma_xy,
                                  params_.relocation_sigma_theta);
    srv.request.stamp = decision_stamp_;
    if (call(local_map_node_ + "/relocate_at_door", &srv) && srv.response.success) return true;
    ROS_WARN("replay_places: cannot re-enter place %d at door %d (%s): a new place instead", a.known_place,
             a.door_id, srv.response.message.c_str());
    return false;
  }

  // The door in the new place (its origin is the robot now).
  void storeDoor(const PlaceAction& a, int place_id) {
    hybrid_slam_msgs::AddDoor door;
    door.request = addDoorRequest(a.door_id, a.door_in_robot);
    if (call(local_map_node_ + "/add_door", &door) && !door.response.success)
      ROS_WARN("replay_places: door not stored in place %d: %s", place_id, door.response.message.c_str());
    else
      ++doors_stored_;
  }

  // The door node's link to the place.
  void linkDoor(const PlaceAction& a, int place_id) {
    hybrid_slam_msgs::UpdateOpening link;
    link.request.node = a.door_node;
    link.request.bearing = a.door_bearing_map;
    link.request.explored = true;
    link.request.place_id = place_id;
    link.request.door_in_place.x = a.door_in_robot.x;
    link.request.door_in_place.y = a.door_in_robot.y;
    link.request.door_in_place.theta = a.door_in_robot.theta;
    if (!call(topo_node_ + "/update_opening", &link)) return;  // call() said why
    if (!link.response.success) {
      ROS_WARN("replay_places: door node %d not linked to place %d: %s", a.door_node, place_id,
               link.response.message.c_str());
      return;
    }
    ++doors_linked_;
  }

  void leave() {
    std_srvs::Trigger srv;
    call(local_map_node_ + "/close_place", &srv);  // closes (and autosaves) even if the reply is lost
    ROS_INFO("replay_places: back in a hallway: place %d closed", places_.place());
    places_.left();
  }

  void publishStatus(const ros::Time& stamp) {
    hybrid_slam_msgs::ExplorationStatus s;
    s.header.stamp = stamp;
    // METRIC pauses pomdp_topo's belief and map building while in a room, as in an exploration.
    s.mode = places_.inPlace() ? s.METRIC : s.TOPOLOGICAL;
    s.current_place = places_.place();
    s.current_node = door_node_;
    s.places = uint32_t(created_);
    s.nodes = uint32_t(nodes_);
    s.travel_distance = places_.travel();
    s.state = places_.inPlace() ? "replay: in place " + std::to_string(places_.place()) : "replay: hallway";
    status_pub_.publish(s);
    last_status_ = stamp;
    last_in_place_ = places_.inPlace();
  }

  // --- the end of the bag -----------------------------------------------------------------------
  void onEndTimer(const ros::WallTimerEvent&) {
    if (finished_) return;
    const ros::WallTime wall = ros::WallTime::now();
    const ros::Time now = ros::Time::now();
    if (now != last_clock_) {
      last_clock_ = now;
      last_clock_wall_ = wall;
    }
    // rosbag play's last clock can fall short of the bag's last message time (its clock ticks at 100 Hz).
    if (bag_end_time_ > 0.0 && now.toSec() >= bag_end_time_ - end_tolerance_) {
      // The last messages are out: let the features of the last scans through, then finish.
      if (end_seen_.isZero()) end_seen_ = wall;
      if ((wall - end_seen_).toSec() >= end_grace_) finish("the bag has ended");
    } else if ((wall - last_clock_wall_).toSec() > end_idle_timeout_) {
      finish(last_clock_.isZero() ? "no clock: the bag did not play" : "the clock stopped before the bag's end");
    }
  }

  void finish(const std::string& why) {
    finished_ = true;
    if (mapping_) {
      if (places_.inPlace()) leave();
      publishStatus(ros::Time::now());
      hybrid_slam_msgs::SaveMap topo, places;
      if (call(topo_node_ + "/save_map", &topo)) ROS_INFO("replay_places: topological map: %s", topo.response.message.c_str());
      if (call(local_map_node_ + "/save_map", &places)) ROS_INFO("replay_places: places: %s", places.response.message.c_str());
    }
    const double wall = (ros::WallTime::now() - wall_start_).toSec();
    size_t lines = 0;
    for (const auto& kv : lines_per_place_) lines += kv.second;
    ROS_INFO("replay_places: %s; %s: %d places created, %d re-entries, %d doors linked, %zu nodes, %zu edges, "
             "%zu lines in the places, %zu feature messages, %.0f s wall",
             why.c_str(), mapping_ ? "hybrid map built" : "features only, no map", created_, reentries_,
             doors_linked_, nodes_, edges_, lines, features_, wall);
    if (!summary_file_.empty()) writeSummary(why, wall);
    ros::WallDuration(0.5).sleep();  // the last status reaches its subscribers first
    ros::requestShutdown();
  }

  void writeSummary(const std::string& why, double wall) {
    std::ofstream f(summary_file_);
    f << "{\"mapping\": " << (mapping_ ? "true" : "false") << ", \"places\": " << created_
      << ", \"reentries\": " << reentries_ << ", \"relocations_ok\": " << relocations_ok_
      << ", \"relocations_failed\": " << relocations_failed_ << ", \"doors_linked\": " << doors_linked_
      << ", \"reentries_refused\": " << reentries_refused_ << ", \"doors_stored\": " << doors_stored_ << ", \"door_crossings\": " << crossings_seen_
      << ", \"nodes\": " << nodes_ << ", \"edges\": " << edges_ << ", \"lines_per_place\": {";
    bool first = true;
    for (const auto& [id, n] : lines_per_place_) {
      f << (first ? "" : ", ") << "\"" << id << "\": " << n;
      first = false;
    }
    f << "}, \"features\": " << features_ << ", \"travel_m\": " << places_.travel()
      << ", \"bag_duration_s\": " << bag_duration_ << ", \"wall_time_s\": " << wall << ", \"end\": \"" << why
      << "\"}\n";
  }

  ros::NodeHandle nh_;
  PassivePlacesParams params_;
  PassivePlaces places_;
  DoorCrossingsParams crossing_params_;
  DoorCrossings crossings_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::string topo_node_, local_map_node_, odom_frame_, base_frame_, summary_file_;
  bool mapping_ = true, finished_ = false, last_in_place_ = false;
  double bag_end_time_ = 0.0, bag_duration_ = 0.0, end_tolerance_ = 1.0, end_grace_ = 2.0, end_idle_timeout_ = 10.0, service_timeout_ = 5.0;
  ros::Publisher status_pub_;
  ros::Subscriber features_sub_, map_sub_, belief_sub_, state_sub_, local_map_sub_, relocation_sub_, map_odom_sub_;
  ros::WallTimer end_timer_;
  ros::WallTime wall_start_, last_clock_wall_, end_seen_;
  ros::Time last_clock_, last_status_;
  std::set<int> door_nodes_;
  std::map<int, size_t> lines_per_place_;
  int door_node_ = -1, created_ = 0, reentries_ = 0, doors_linked_ = 0, doors_stored_ = 0, crossings_seen_ = 0, reentries_refused_ = 0, awaiting_verdict_ = -1, relocations_ok_ = 0, relocations_failed_ = 0;
  double heading_map_ = 0.0;
  Pose2D map_odom_;
  double reentry_travel_ = 0.0;  // m, places_.travel() at the last re-entry
  ros::Time decision_stamp_;     // the stamp of the scan (or verdict) the current action was decided at
  size_t nodes_ = 0, edges_ = 0, features_ = 0;
};

}  // namespace
}  // namespace exploration

int main(int argc, char** argv) { return laser_features::runNode<exploration::ReplayPlacesNode>(argc, argv, "replay_places"); }
