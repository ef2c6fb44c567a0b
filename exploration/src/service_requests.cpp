#include "service_requests.h"

#include <hybrid_slam_msgs/AddDoor.h>
#include <hybrid_slam_msgs/CreatePlace.h>
#include <hybrid_slam_msgs/RelocateAtDoor.h>
#include <hybrid_slam_msgs/ResetBelief.h>
#include <hybrid_slam_msgs/SaveMap.h>
#include <hybrid_slam_msgs/UpdateOpening.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include "ros_conversions.h"
#include "service_call.h"

namespace exploration {

template <typename Srv>
bool ServiceRequests::call(const std::string& name, Srv* srv, int attempts) {
  return callService(nh_, "exploration", name, srv, kServiceTimeout, attempts);
}

void ServiceRequests::execute(const Request& r, Coordinator* coordinator) {
  switch (r.kind) {
    case Request::CreatePlace: {
      hybrid_slam_msgs::CreatePlace srv;
      srv.request.use_display_pose = false;
      const bool ok = call(local_map_node_ + "/create_place", &srv, 2) && srv.response.success;
      if (!ok) ROS_ERROR("exploration: no place created: %s", srv.response.message.c_str());
      else ROS_INFO("exploration: %s", srv.response.message.c_str());
      coordinator->placeCreated(ok, srv.response.place_id);
      break;
    }
    case Request::AddDoor: {
      hybrid_slam_msgs::AddDoor srv;
      srv.request = addDoorRequest(r.door_id, r.pose);
      if (call(local_map_node_ + "/add_door", &srv) && !srv.response.success)
        ROS_WARN("exploration: door not stored in the place: %s", srv.response.message.c_str());
      break;
    }
    case Request::RecordOpening: {
      hybrid_slam_msgs::UpdateOpening srv;
      srv.request.node = r.node;
      srv.request.bearing = r.bearing;
      srv.request.width = r.width;
      srv.request.offset = r.offset;
      srv.request.explored = r.explored;
      srv.request.beside_robot = r.beside_robot;
      srv.request.place_id = r.place_id;
      srv.request.door_in_place.x = r.pose.x;
      srv.request.door_in_place.y = r.pose.y;
      srv.request.door_in_place.theta = r.pose.theta;
      const bool ok = call(topo_node_ + "/update_opening", &srv) && srv.response.success;
      if (!ok) ROS_WARN("exploration: opening not recorded: %s", srv.response.message.c_str());
      if (ok && r.store_in_place && r.place_id >= 0 && srv.response.node >= 0) {
        hybrid_slam_msgs::AddDoor add;
        add.request = addDoorInPlaceRequest(r.place_id, srv.response.node, r.pose);
        if (call(local_map_node_ + "/add_door", &add) && !add.response.success)
          ROS_WARN("exploration: door not stored in place %d: %s", r.place_id, add.response.message.c_str());
      }
      coordinator->openingRecorded(ok, srv.response.node);
      break;
    }
    case Request::ClosePlace: {
      std_srvs::Trigger srv;
      call(local_map_node_ + "/close_place", &srv);
      break;
    }
    case Request::SaveMaps: {
      hybrid_slam_msgs::SaveMap topo;
      if (call(topo_node_ + "/save_map", &topo)) ROS_INFO("exploration: topological map: %s", topo.response.message.c_str());
      hybrid_slam_msgs::SaveMap places;
      if (call(local_map_node_ + "/save_map", &places)) ROS_INFO("exploration: places: %s", places.response.message.c_str());
      break;
    }
    case Request::Finish:
      break;  // the node's: it ends the run
    case Request::Relocate: {
      hybrid_slam_msgs::RelocateAtDoor srv;
      // The door as the laser saw it from the hallway: a few centimetres and degrees; back in a host
      // room from the room behind, the EKF's pose in that room, with its covariance.
      srv.request = r.pose_cov ? relocateRequest(r.place_id, r.door_id, r.pose, *r.pose_cov)
                               : relocateRequest(r.place_id, r.door_id, r.pose, sigma_xy_, sigma_theta_);
      const bool ok = call(local_map_node_ + "/relocate_at_door", &srv) && srv.response.success;
      if (!ok) {
        ROS_WARN("exploration: relocation not started: %s", srv.response.message.c_str());
        coordinator->relocationResult(r.place_id, false, "not started: " + srv.response.message);
      }
      break;
    }
    case Request::ResetBelief: {
      hybrid_slam_msgs::ResetBelief srv;
      srv.request.uniform = true;
      if (call(topo_node_ + "/reset_belief", &srv)) ROS_INFO("exploration: %s", srv.response.message.c_str());
      break;
    }
  }
}

bool ServiceRequests::setMapping(bool mapping, std::string* message) {
  std_srvs::SetBool srv;
  srv.request.data = mapping;
  const bool ok = call(topo_node_ + "/set_mapping", &srv);
  *message = srv.response.message;
  return ok;
}

}  // namespace exploration
