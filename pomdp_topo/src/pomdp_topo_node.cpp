// pomdp_topo_node: the topological half of the hybrid map (Tomatis et al. 2001, section 3.3). Feeds
// the core the features of each scan and the odometry (tf odom -> base_link at the scan's stamp);
// builds the graph, localizes on it with the POMDP, closes loops; publishes the map, the belief and
// markers; saves and loads the map.
#include <hybrid_slam_msgs/BuildingAxes.h>
#include <hybrid_slam_msgs/ExplorationStatus.h>
#include <hybrid_slam_msgs/LoadMap.h>
#include <hybrid_slam_msgs/ResetBelief.h>
#include <hybrid_slam_msgs/SaveMap.h>
#include <hybrid_slam_msgs/UpdateOpening.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>
#include <tf2/utils.h>
#include <tf2_ros/transform_listener.h>

#include <sys/stat.h>

#include <cmath>

#include "laser_features/building_rules_ros.h"
#include "laser_features/param_reader_ros.h"
#include "laser_features/tf_lookup.h"
#include "laser_features/node_main_ros.h"
#include "lockstep/participant.h"
#include "pomdp_topo/map_io.h"
#include "pomdp_topo/params_visit.h"
#include "ros_conversions.h"

namespace pomdp_topo {
namespace {

TopoParams readParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) {
  TopoParams p;
  visitParams(&p, laser_features::RosParamReader{pnh});
  p.builder.rules = laser_features::readBuildingRules(nh);
  p.front_end.tracks = laser_features::readOpeningTracks(nh);
  p.sync();
  std::string why;
  if (!validateParams(p, &why)) throw std::invalid_argument("parameter " + why);
  return p;
}

int readRealignUpdates(const ros::NodeHandle& pnh) {
  int updates = 20;
  pnh.param("realign_updates", updates, updates);
  if (updates < 1) throw std::invalid_argument("parameter realign_updates must be >= 1");
  return updates;
}

bool fileExists(const std::string& path) {
  struct stat st;
  return !path.empty() && ::stat(path.c_str(), &st) == 0;
}

class TopoNodeRos {
 public:
  TopoNodeRos(ros::NodeHandle nh, ros::NodeHandle pnh)
      : nh_(nh),
        params_(readParams(nh, pnh)),
        localizer_(params_.pomdp),
        front_end_(params_.front_end, params_.heading),
        builder_(&map_, &localizer_, params_.builder),
        realigner_(params_.pomdp.heading_bins, readRealignUpdates(pnh)),
        axis_estimator_(params_.axis),
        tf_listener_(tf_buffer_, true, lockstep::kTransportHints),
        lockstep_(nh, {"laser_features"}) {
    pnh.param<std::string>("map_frame", map_frame_, "map");
    pnh.param<std::string>("odom_frame", odom_frame_, "odom");
    pnh.param<std::string>("base_frame", base_frame_, "base_link");
    pnh.param<std::string>("map_file", map_file_, "");
    pnh.param("load_on_start", load_on_start_, true);
    pnh.param("autosave", autosave_, true);
    pnh.param("transform_timeout", transform_timeout_, 0.1);
    transform_timeout_ = lockstep_.transformTimeout(transform_timeout_);
    pnh.param("markers_period", markers_period_, 0.5);
    pnh.param("kidnap_consistency", kidnap_consistency_, 0.75);

    map_pub_ = lockstep_.advertise<hybrid_slam_msgs::TopologicalMap>(nh_, "topological_map", 1, true);
    belief_pub_ = lockstep_.advertise<hybrid_slam_msgs::TopologicalBelief>(nh_, "topological_belief", 10);
    state_pub_ = lockstep_.advertise<hybrid_slam_msgs::TopologicalState>(nh_, "topological_state", 10, true);
    events_pub_ = lockstep_.advertise<hybrid_slam_msgs::TopoEvent>(nh_, "topo_events", 100);
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("topo_markers", 2, true);
    axes_pub_ = lockstep_.advertise<hybrid_slam_msgs::BuildingAxes>(nh_, "building_axes", 1, true);
    // In lockstep, the features of a step wait for laser_features' acknowledgement of it.
    features_sub_ = lockstep_.subscribe(nh_, "features", 20, &TopoNodeRos::onFeatures, this, lockstep::Delivery::Gated);
    status_sub_ = lockstep_.subscribe<hybrid_slam_msgs::ExplorationStatus>(
        nh_, "exploration_status", 10, [this](const hybrid_slam_msgs::ExplorationStatus::ConstPtr& m) { onStatus(*m); });
    services_ = {
        pnh.advertiseService("save_map", &TopoNodeRos::onSave, this),
        pnh.advertiseService("load_map", &TopoNodeRos::onLoad, this),
        pnh.advertiseService("clear_map", &TopoNodeRos::onClear, this),
        pnh.advertiseService("reset_belief", &TopoNodeRos::onReset, this),
        pnh.advertiseService("update_opening", &TopoNodeRos::onUpdateOpening, this),
        pnh.advertiseService("set_mapping", &TopoNodeRos::onSetMapping, this),
    };
    if (load_on_start_ && fileExists(map_file_)) {
      const IoResult r = loadMap(map_file_, &map_);
      if (r) {
        ROS_INFO("pomdp_topo: loaded %zu nodes and %zu edges from %s", map_.nodeCount(), map_.edgeCount(), map_file_.c_str());
      } else {
        ROS_ERROR("pomdp_topo: %s; starting with an empty map", r.error.c_str());
      }
    }
    if (!params_.axis_from_walls) setAxes(params_.pomdp.axis_angle, hybrid_slam_msgs::BuildingAxes::PARAMETER);
    else if (map_.edgeCount() > 0) setAxesFromMap();
    publishMap();
  }

 private:
  bool lookup(const std::string& target, const std::string& source, const ros::Time& stamp, Pose2D* out,
              std::string* why) {
    return laser_features::lookupPose2D(tf_buffer_, target, source, stamp, transform_timeout_, out, why);
  }

  void onStatus(const hybrid_slam_msgs::ExplorationStatus& msg) {
    // In a room (METRIC) the topological map stands still; the robot comes back to the hallway
    // where it left it, so the travel in between is not the hallway's.
    const bool paused = msg.mode == hybrid_slam_msgs::ExplorationStatus::METRIC;
    if (paused && !paused_) {
      paused_travel_ = front_end_.travel();
      paused_bin_ = front_end_.headingBin();
      paused_pending_ = front_end_.pendingTravel();
      paused_wing_offset_ = front_end_.wingOffset();
    }
    if (!paused && paused_) {
      builder_.skipTravel(front_end_.travel() - paused_travel_);
      // The turns and travel in the room are not the hallway's; the hallway travel not yet emitted
      // as an action when the robot left is (else each room visit loses up to a cell).
      front_end_.setHeadingBin(paused_bin_, paused_pending_, paused_wing_offset_);
    }
    paused_ = paused;
  }

  // The building's axis, the heading of bin 0 for everything mapped (BuildingAxisEstimator): set
  // in every piece that bins headings, and published for the other nodes.
  void setAxes(double axis, uint8_t source, double agreement = 0.0, double wall_length = 0.0) {
    params_.pomdp.axis_angle = axis;
    params_.sync();
    front_end_.setAxis(axis);
    builder_.setAxis(axis);
    localizer_.setAxis(axis);
    axes_known_ = true;
    hybrid_slam_msgs::BuildingAxes msg;
    msg.header.stamp = last_stamp_.isZero() ? ros::Time::now() : last_stamp_;
    msg.header.frame_id = map_frame_;
    msg.axis_angle = axis;
    msg.heading_bins = uint32_t(params_.pomdp.heading_bins);
    msg.source = source;
    msg.agreement = agreement;
    msg.wall_length = wall_length;
    axes_pub_.publish(msg);
    const char* from = source == hybrid_slam_msgs::BuildingAxes::ESTIMATED ? "the walls"
                       : source == hybrid_slam_msgs::BuildingAxes::FROM_MAP ? "the loaded map's edges"
                                                                              : "the axis_angle parameter";
    ROS_INFO("pomdp_topo: the building's axis is %.1f deg in the map frame (from %s; agreement %.3f over %.1f m of wall)",
             axis * 180.0 / M_PI, from, agreement, wall_length);
  }

  void setAxesFromMap() {
    std::vector<double> headings, lengths;
    for (const auto& kv : map_.edges()) {
      headings.push_back(kv.second.heading);
      lengths.push_back(std::max(kv.second.length, 1e-3));
    }
    setAxes(laser_features::dominantAxis(headings, lengths), hybrid_slam_msgs::BuildingAxes::FROM_MAP);
  }

  /// Feeds the wall lines of a scan to the axis estimate; true once the axis is known. The map
  /// frame is the odometry frame until the first scan is processed, so a line's normal in it is the
  /// odometry heading plus the line's alpha in the robot frame.
  bool findAxes(const Pose2D& odom) {
    for (const auto& l : lines_) axis_estimator_.add(odom.theta + l.line.alpha, l.line.cov(0, 0), l.length());
    ++axis_scans_;
    if (axis_estimator_.ready()) {
      setAxes(axis_estimator_.axis(), hybrid_slam_msgs::BuildingAxes::ESTIMATED, axis_estimator_.agreement(),
              axis_estimator_.totalLength());
      return true;
    }
    if (axis_scans_ >= params_.axis_max_scans) {
      ROS_WARN("pomdp_topo: no agreed walls in %d scans (%.1f m of lines, agreement %.2f < %.2f); the building's axis is "
               "the axis_angle parameter", axis_scans_, axis_estimator_.totalLength(), axis_estimator_.agreement(),
               params_.axis.min_agreement);
      setAxes(params_.pomdp.axis_angle, hybrid_slam_msgs::BuildingAxes::PARAMETER);
      return true;
    }
    ROS_INFO_THROTTLE(2.0, "pomdp_topo: finding the building's axis from the walls (%.1f m of lines so far)",
                      axis_estimator_.totalLength());
    return false;
  }

  void onFeatures(const hybrid_slam_msgs::LaserFeatures::ConstPtr& msg) {
    if (!last_stamp_.isZero() && msg->header.stamp <= last_stamp_) {
      ROS_WARN_THROTTLE(5.0, "pomdp_topo: features at %.3f are not newer than the last ones (%.3f) on %s; dropped",
                        msg->header.stamp.toSec(), last_stamp_.toSec(), features_sub_.getTopic().c_str());
      return;
    }
    Pose2D sensor, odom;
    std::string why;
    if (!lookup(base_frame_, msg->header.frame_id, msg->header.stamp, &sensor, &why) ||
        !lookup(odom_frame_, base_frame_, msg->header.stamp, &odom, &why)) {
      ROS_WARN_THROTTLE(5.0, "pomdp_topo: no transform for the features of frame '%s': %s", msg->header.frame_id.c_str(),
                        why.c_str());
      return;
    }
    last_stamp_ = msg->header.stamp;
    size_t dropped = 0;
    fromMsg(*msg, sensor, &lines_, &corners_, &openings_, &dropped);
    if (dropped > 0) {
      ROS_WARN_THROTTLE(10.0, "pomdp_topo: %zu feature(s) with non-finite numbers dropped from %s", dropped,
                        features_sub_.getTopic().c_str());
    }
    // Nothing is mapped before the building's axis is known: every heading is binned along it.
    if (!axes_known_ && !findAxes(odom)) return;
    const bool first = !front_end_.initialized();
    if (first) front_end_.reset(odom, odom.theta, params_.heading.initial_variance);
    actions_.clear();
    if (!front_end_.process(odom, lines_, corners_, openings_, &actions_, &why)) {
      ROS_WARN_THROTTLE(5.0, "pomdp_topo: %s; the scan is skipped", why.c_str());
      builder_.positionLost();
      realigner_.setTrusted(false);
      return;
    }
    if (first) {
      builder_.start(front_end_);
      realigner_.setTrusted(map_.empty());  // a map built from here on has the odometry's heading
    }
    // A scan the odometry does not explain: the robot was moved (kidnapped) and its place is unknown.
    // Not before the map has two nodes: a belief over one node is 'confident' at once, and a false
    // alarm there would move the whole map.
    if (!first && !paused_ && kidnap_consistency_ > 0.0 && map_.nodeCount() >= 2 &&
        msg->odometry_consistency >= 0.0 && msg->odometry_consistency < kidnap_consistency_) {
      ROS_WARN("pomdp_topo: odometry consistency %.2f < %.2f: the robot was moved; belief reset to uniform",
               msg->odometry_consistency, kidnap_consistency_);
      front_end_.clearTracks();
      builder_.odometryJump(front_end_);
      realigner_.setTrusted(false);
      publishMap();  // a reopened opening is no structural change (no new revision) but must be seen
      if (autosave_ && !map_file_.empty()) save(map_file_, nullptr);
    }
    if (paused_) {
      front_end_.takePassed();  // in a room: the topological map does not move
      return;
    }
    const Observation observation = front_end_.observation();
    builder_.setHeadingTrusted(realigner_.trusted());
    builder_.process(actions_, observation, front_end_.takePassed(), front_end_);
    Eigen::Vector2d relocated;
    if (builder_.takeRelocatedPosition(&relocated)) front_end_.setPosition(relocated);
    if (localizer_.lostResets() != lost_resets_) {
      lost_resets_ = localizer_.lostResets();
      ROS_WARN("pomdp_topo: the belief is lost (the map does not explain the observations or a turn); reset to uniform");
      publishEvent(TopoEvent{TopoEvent::Kind::BeliefLost, -1, -1, -1, "belief lost: reset to uniform"}, msg->header.stamp);
    }
    if (!actions_.empty()) realignHeading();
    for (const TopoEvent& e : builder_.takeEvents()) {
      ROS_INFO("pomdp_topo: %s", e.text.c_str());
      publishEvent(e, msg->header.stamp);
    }
    if (map_.revision() != published_revision_) {
      publishMap();
      if (autosave_ && !map_file_.empty() && builder_.mode() != MapBuilder::Mode::LoopCheck) save(map_file_, nullptr);
    }
    std_msgs::Header header;
    header.stamp = msg->header.stamp;
    header.frame_id = map_frame_;
    if (!actions_.empty() || first) {
      hybrid_slam_msgs::TopologicalBelief belief;
      toMsg(localizer_, header, &belief);
      belief_pub_.publish(belief);
    }
    hybrid_slam_msgs::TopologicalState state;
    const Pose2D pose = front_end_.pose();
    toMsg(builder_.mode(), builder_.confident(), Pose2D{pose.x, pose.y, front_end_.heading().theta()}, header, &state);
    state_pub_.publish(state);
    if ((msg->header.stamp - last_markers_).toSec() >= markers_period_) {
      last_markers_ = msg->header.stamp;
      visualization_msgs::MarkerArray markers;
      toMarkers(map_, localizer_, header, &markers);
      markers_pub_.publish(markers);
    }
  }

  // After a kidnapping the heading estimate may be off by whole bins: once the belief is confident
  // again, its most likely heading wins (HeadingRealigner: not while the heading is trusted).
  void realignHeading() {
    if (builder_.mode() != MapBuilder::Mode::Localized || !localizer_.confident()) return;
    const int ml = localizer_.mostLikely();
    if (ml < 0) return;
    const int k = realigner_.update(localizer_.headingBin(localizer_.state(size_t(ml)).heading), front_end_.headingBin());
    if (k == 0) return;
    ROS_WARN("pomdp_topo: heading estimate re-aligned by %d bin(s) to the localized state", k);
    front_end_.shiftHeading(k);
  }

  void publishEvent(const TopoEvent& event, const ros::Time& stamp) {
    std_msgs::Header header;
    header.stamp = stamp;
    header.frame_id = map_frame_;
    hybrid_slam_msgs::TopoEvent msg;
    toMsg(event, header, &msg);
    events_pub_.publish(msg);
  }

  void publishMap() {
    hybrid_slam_msgs::TopologicalMap msg;
    std_msgs::Header header;
    header.stamp = last_stamp_.isZero() ? ros::Time::now() : last_stamp_;
    header.frame_id = map_frame_;
    toMsg(map_, header, &msg);
    map_pub_.publish(msg);
    published_revision_ = map_.revision();
    // The markers follow every change of the map (latched: a map shown without a robot has them).
    visualization_msgs::MarkerArray markers;
    toMarkers(map_, localizer_, header, &markers);
    markers_pub_.publish(markers);
  }

  bool save(const std::string& path, std::string* message) {
    const IoResult r = saveMap(map_, path);
    if (!r) ROS_ERROR_THROTTLE(10.0, "pomdp_topo: %s", r.error.c_str());
    if (message) *message = r ? "saved " + std::to_string(map_.nodeCount()) + " nodes to " + path : r.error;
    return bool(r);
  }

  bool onSave(hybrid_slam_msgs::SaveMap::Request& req, hybrid_slam_msgs::SaveMap::Response& res) {
    const std::string path = req.path.empty() ? map_file_ : req.path;
    if (path.empty()) {
      res.success = false;
      res.message = "no path given and the map_file parameter is empty";
      return true;
    }
    res.success = save(path, &res.message);
    return true;
  }

  bool onLoad(hybrid_slam_msgs::LoadMap::Request& req, hybrid_slam_msgs::LoadMap::Response& res) {
    const std::string path = req.path.empty() ? map_file_ : req.path;
    const IoResult r = loadMap(path, &map_);
    res.success = bool(r);
    if (!r) {
      res.message = r.error + "; the map in memory is kept";
      ROS_ERROR("pomdp_topo: %s", res.message.c_str());
      return true;
    }
    res.message = "loaded " + std::to_string(map_.nodeCount()) + " nodes and " + std::to_string(map_.edgeCount()) + " edges";
    if (params_.axis_from_walls && map_.edgeCount() > 0) setAxesFromMap();
    if (front_end_.initialized()) builder_.start(front_end_);  // localized, uniform belief
    else localizer_.setMap(map_);
    realigner_.setTrusted(false);  // the loaded map's frame is not the odometry's
    publishMap();
    return true;
  }

  bool onClear(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    map_.clear();
    if (front_end_.initialized()) builder_.start(front_end_);
    else localizer_.setMap(map_);
    realigner_.setTrusted(true);  // the map is built anew from the odometry's heading
    publishMap();
    res.success = true;
    res.message = "map cleared";
    return true;
  }

  bool onReset(hybrid_slam_msgs::ResetBelief::Request& req, hybrid_slam_msgs::ResetBelief::Response& res) {
    if (localizer_.mapRevision() != map_.revision()) localizer_.setMap(map_);
    if (req.uniform) {
      localizer_.setUniform();
      res.success = true;
      res.message = "belief uniform over " + std::to_string(localizer_.size()) + " states";
      return true;
    }
    if (!std::isfinite(req.heading) || !localizer_.resetToNode(req.node, req.heading)) {
      res.success = false;
      res.message = "no node " + std::to_string(req.node) + " in the map (or a non-finite heading); belief unchanged";
      return true;
    }
    res.success = true;
    res.message = "belief on node " + std::to_string(req.node);
    return true;
  }

  bool onSetMapping(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    builder_.setMapping(req.data);
    res.success = true;
    res.message = req.data ? "mapping on" : "mapping off: localization only, the map is not changed";
    ROS_INFO("pomdp_topo: %s", res.message.c_str());
    return true;
  }

  bool onUpdateOpening(hybrid_slam_msgs::UpdateOpening::Request& req,
                       hybrid_slam_msgs::UpdateOpening::Response& res) {
    res.success = false;
    NodeOpening o;
    o.bearing = req.bearing;
    // A new opening is seen from the hallway the robot left (bearings come on the heading bins).
    o.skew = paused_ ? paused_wing_offset_ : front_end_.wingOffset();
    o.offset = req.offset;
    o.width = req.width;
    o.explored = req.explored;
    const auto& d = req.door_in_place;
    if (!std::isfinite(req.offset) || !std::isfinite(req.width) || !std::isfinite(d.x) || !std::isfinite(d.y) ||
        !std::isfinite(d.theta)) {
      res.message = "non-finite offset, width or door pose";
      return true;
    }
    int id = req.node;
    if (id < 0) id = req.beside_robot ? builder_.nodeBesideRobot(o, front_end_) : builder_.currentNode();
    if (id < 0) {
      res.message = "the robot's node is unknown (no map or an unconfident belief)";
      return true;
    }
    if (!map_.recordOpening(uint32_t(id), o)) {
      res.message = "no node " + std::to_string(id) + " (or a non-finite bearing)";
      return true;
    }
    res.success = true;
    res.node = id;
    res.message = "node " + std::to_string(id) + " updated";
    int32_t linked = -1;
    if (req.place_id >= 0 && !map_.linkPlace(uint32_t(id), o, req.place_id, Pose2D{d.x, d.y, d.theta}, &linked)) {
      // A door links one place, the first: a room entered again through a known door is mapped
      // twice, and missions name the first map.
      res.message += "; place " + std::to_string(req.place_id) + " not linked: the door links place " +
                     std::to_string(linked);
      ROS_WARN_STREAM("pomdp_topo: " << res.message);
    }
    publishMap();
    if (autosave_ && !map_file_.empty()) save(map_file_, nullptr);
    return true;
  }

  ros::NodeHandle nh_;
  TopoParams params_;
  TopologicalMap map_;
  PomdpLocalizer localizer_;
  FrontEnd front_end_;
  MapBuilder builder_;
  HeadingRealigner realigner_;
  laser_features::BuildingAxisEstimator axis_estimator_;
  bool axes_known_ = false;
  int axis_scans_ = 0;  // scans fed to axis_estimator_
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::string map_frame_, odom_frame_, base_frame_, map_file_;
  bool load_on_start_ = true, autosave_ = true;
  double transform_timeout_ = 0.1, markers_period_ = 0.5;
  double kidnap_consistency_ = 0.75;
  lockstep::Participant lockstep_;
  lockstep::Publisher map_pub_, belief_pub_, state_pub_, events_pub_, axes_pub_;
  ros::Publisher markers_pub_;
  ros::Subscriber features_sub_, status_sub_;
  std::vector<ros::ServiceServer> services_;
  ros::Time last_stamp_, last_markers_;
  uint64_t published_revision_ = ~0ull;
  bool paused_ = false;
  double paused_travel_ = 0.0;  // m, FrontEnd::travel() when the map was paused
  int paused_bin_ = 0;          // FrontEnd::headingBin() then
  double paused_pending_ = 0.0; // m, FrontEnd::pendingTravel() then
  double paused_wing_offset_ = 0.0;  // rad, FrontEnd::wingOffset() then
  uint64_t lost_resets_ = 0;
  std::vector<laser_features::LineSegment> lines_;
  std::vector<laser_features::Corner> corners_;
  std::vector<laser_features::Opening> openings_;
  std::vector<Action> actions_;
};

}  // namespace
}  // namespace pomdp_topo

int main(int argc, char** argv) { return laser_features::runNode<pomdp_topo::TopoNodeRos>(argc, argv, "pomdp_topo"); }
