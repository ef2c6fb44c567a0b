#include "exploration/room_sequence.h"

#include <algorithm>
#include <cstdio>

namespace exploration {

using laser_features::Pose2D;

RoomSequence::RoomSequence(const RoomVisitParams& params, const RoomExplorerParams& room,
                           const laser_features::BuildingRules& rules, const HallwayDoorParams& doors)
    : inner_rooms_(params.inner_rooms), host_(params, room, rules, doors), suite_(params, room, rules, doors) {}

void RoomSequence::setStep(Step s, double now, const std::string& text) {
  step_ = s;
  step_since_ = now;
  text_ = text;
}

void RoomSequence::beginNewRoom(const Pose2D& robot_odom, const DoorTrack& door, double hallway_heading_odom,
                                int place_id, double now) {
  host_.beginNewRoom(robot_odom, door, hallway_heading_odom);
  setStep(Step::ApproachDoor, now, "entering the room of place " + std::to_string(place_id));
}

void RoomSequence::beginKnownRoom(const Perception& p, const Pose2D& hallway_pose_odom, double hallway_heading_odom,
                                  const GraphOpening& opening, double door_width, int place_id, double now) {
  host_.beginKnownRoom(p, hallway_pose_odom, hallway_heading_odom, opening, door_width);
  setStep(Step::ApproachDoor, now, "relocated in place " + std::to_string(place_id) + ": entering");
}

void RoomSequence::beginExit(const std::string& text, double now) {
  host_.beginExit();
  setStep(Step::ExitPath, now, text);
}

Perception RoomSequence::observe(const Perception& p, bool approaching, Decision* d) {
  const Perception q = visit().inPlace(p);
  visit().observe(q, approaching, d);
  if (suite_.insideInner()) suite_.observeInner(q);
  return q;
}

RoomSequence::Outcome RoomSequence::step(const Perception& p, double now, const MotionFeedback& motion, bool mission,
                                         double travel, Places* places, Decision* d) {
  now_ = now;
  last_odom_ = p.odom;
  if (step_ == Step::InnerPlace) {
    createInnerPlace(p, places, d);
    return Outcome::Inside;
  }
  const Perception q = observe(p, step_ == Step::ApproachDoor, d);
  switch (step_) {
    case Step::ApproachDoor:
      return approachDoor(q, mission, d);
    case Step::Cover:
      return coverRoom(q, travel, *places, d);
    case Step::ToInnerDoor:
      toInnerDoor(q, *places, d);
      return Outcome::Inside;
    case Step::PeekInner:
      peekInner(q, places, d);
      return Outcome::Inside;
    default:
      return leaveRoom(q, motion, places, d);
  }
}

RoomSequence::Outcome RoomSequence::approachDoor(const Perception& q, bool mission, Decision* d) {
  if (!visit().approachDoor(q, now_ - step_since_, d)) return Outcome::Inside;
  if (mission) return Outcome::AtDoor;
  const double shift = visit().doorRefinement();
  char text[96];
  std::snprintf(text, sizeof(text), "exploring the room (its door refined by %.2f m)", shift);
  setStep(Step::Cover, now_, shift > 0.0 ? text : "exploring the room");
  return Outcome::Inside;
}

RoomSequence::Outcome RoomSequence::coverRoom(const Perception& q, double travel, const Places& places, Decision* d) {
  const RoomVisit::Coverage coverage = visit().coverRoom(q, now_, now_ - step_since_, d);
  if (coverage == RoomVisit::Coverage::Covering) return Outcome::Inside;
  if (coverage == RoomVisit::Coverage::TimedOut) ++stats_.rooms_left_early;
  stats_.room_free_area += visit().explorer().freeArea();
  stats_.peak_room_bytes = std::max(stats_.peak_room_bytes, visit().explorer().bytes());
  if (suite_.insideInner()) {
    suite_.roomCovered(visit(), travel);
    visit().beginExit();
    setStep(Step::ExitPath, now_, "leaving the room by its door back into place " + std::to_string(host_place_id_));
    return Outcome::Inside;
  }
  // The host room is covered: the rooms behind its inner doors first, then its way out.
  if (inner_rooms_) {
    host_.openFurnitureGaps();
    suite_.begin(host_, travel);
    suite_.roomCovered(host_, travel);
    if (toNextInnerRoom(q, places)) return Outcome::Inside;
  }
  exitHost();
  return Outcome::Inside;
}

void RoomSequence::exitHost() {
  host_.closeFurnitureGaps();
  host_.beginExit();
  const std::string unreached = suite_.takeUnreached();
  setStep(Step::ExitPath, now_, (unreached.empty() ? "" : unreached + ": given up; ") + "leaving the room by its door");
}

bool RoomSequence::toNextInnerRoom(const Perception& q, const Places& places) {
  if (!suite_.nextDoor(host_, Eigen::Vector2d(q.room_pose.x, q.room_pose.y))) return false;
  setStep(Step::ToInnerDoor, now_, "to a door into a room behind place " + std::to_string(places.place_id));
  return true;
}

void RoomSequence::toInnerDoor(const Perception& q, const Places& places, Decision* d) {
  const SuiteVisit::Drive drive = suite_.driveToDoor(host_, q, now_ - step_since_, d);
  if (drive == SuiteVisit::Drive::Driving) return;
  if (drive == SuiteVisit::Drive::Failed) {
    if (!toNextInnerRoom(q, places)) exitHost();
    return;
  }
  setStep(Step::PeekInner, now_, "looking through the door of place " + std::to_string(places.place_id));
}

void RoomSequence::peekInner(const Perception& q, Places* places, Decision* d) {
  const SuiteVisit::Drive drive = suite_.peek(host_, q, now_ - step_since_, d);
  if (drive == SuiteVisit::Drive::Driving) return;
  if (drive == SuiteVisit::Drive::Failed || suite_.behind() != SuiteVisit::Behind::Room) {
    std::string seen = "the look through the door timed out";
    if (drive == SuiteVisit::Drive::There) {
      ++stats_.inner_doors_left;
      seen = suite_.behind() == SuiteVisit::Behind::Hallway
                 ? "a hallway behind the door (" + suite_.space() + "), no room"
                 : "a room with a door onto the hallway behind the door (" + suite_.space() + "): left to the hallway";
    }
    if (!toNextInnerRoom(q, *places)) exitHost();
    text_ = seen + "; " + text_;  // the verdict in the log, with what follows
    return;
  }
  // Back in front of the door: a place for the room behind, the robot standing still at its origin,
  // which the host keeps (SuiteVisit::keepOrigin) to be relocated at on the way back.
  d->stop = true;
  host_place_id_ = places->place_id;
  places->place_ok = false;
  d->requests.push_back(suite_.keepOrigin(host_place_id_));
  d->requests.push_back(Request{Request::CreatePlace});
  setStep(Step::InnerPlace, now_,
          "creating a place for the room behind place " + std::to_string(host_place_id_) + " (" + suite_.space() + ")");
}

void RoomSequence::createInnerPlace(const Perception& p, Places* places, Decision* d) {
  d->stop = true;
  if (!places->place_ok) {
    places->place_id = host_place_id_;
    if (!toNextInnerRoom(host_.inPlace(p), *places)) exitHost();
    return;
  }
  suite_.beginInnerRoom(host_, p.odom);
  ++stats_.inner_rooms;
  setStep(Step::ApproachDoor, now_, "entering the room of place " + std::to_string(places->place_id) + " from place " +
                                        std::to_string(host_place_id_));
}

void RoomSequence::backInHost(const Perception& q, Places* places, Decision* d) {
  // The room behind is done: its place closed, the host's again, relocated where the robot is
  // (SuiteVisit::relocateHost; the EKF tracks one place).
  d->requests.push_back(Request{Request::ClosePlace});
  d->requests.push_back(suite_.relocateHost(host_place_id_, q));
  suite_.endInnerRoom();
  places->place_id = host_place_id_;
  Perception h;
  h.odom = last_odom_;
  h = host_.inPlace(h);  // until the EKF's first pose of the host: the odometry since its last one
  if (!toNextInnerRoom(h, *places)) exitHost();
}

RoomSequence::Outcome RoomSequence::leaveRoom(const Perception& q, const MotionFeedback& motion, Places* places,
                                              Decision* d) {
  if (step_ == Step::ExitPath) {
    if (!visit().followExitPath(q, now_ - step_since_, d)) return Outcome::Inside;
    setStep(Step::ExitDoor, now_,
            suite_.insideInner() ? "through the door back into place " + std::to_string(host_place_id_)
                                 : "through the door back to the hallway");
    visit().beginDoorExit(now_);
  }
  const RoomVisit::Exit exit = visit().exitThroughDoor(q, now_, now_ - step_since_, motion, d);
  if (exit == RoomVisit::Exit::Passing) return Outcome::Inside;
  if (exit == RoomVisit::Exit::TryAgain) {
    setStep(Step::ExitPath, now_,
            "still inside: leaving the room by its door again (attempt " + std::to_string(visit().exitAttempts() + 1) +
                ")");
    return Outcome::Inside;
  }
  // Still inside after every attempt: never on as on a hallway (the room would be taken for
  // hallways). The coordinator stops the exploration; a mission ends, the robot in the room, whose
  // next mission leaves it afresh.
  if (exit == RoomVisit::Exit::Stuck) {
    why_ = "could not leave place " + std::to_string(places->place_id) + " through its door (" +
           std::to_string(RoomVisit::kExitAttempts) + " attempts)";
    return Outcome::Stuck;
  }
  if (suite_.insideInner()) {
    backInHost(q, places, d);
    return Outcome::Inside;
  }
  return exit == RoomVisit::Exit::Back ? Outcome::Out : Outcome::OutInexact;
}

}  // namespace exploration
