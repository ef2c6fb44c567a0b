// The world as a Bullet collision world: the robot's motion is swept against it so that it never
// passes through an obstacle at any speed.
#pragma once

#include <btBulletCollisionCommon.h>

#include <memory>
#include <vector>

#include "bullet_sim/world.h"

namespace bullet_sim {

struct SweepResult {
  double fraction = 1.0;  // of the requested motion that is free (1: no contact)
  bool contact = false;
};

class CollisionWorld {
 public:
  CollisionWorld(const World& world, double robot_radius);
  ~CollisionWorld();
  CollisionWorld(const CollisionWorld&) = delete;
  CollisionWorld& operator=(const CollisionWorld&) = delete;

  // Sweeps the robot's footprint from `from` to `to` (x, y in the world frame). Contacts that the
  // motion leaves (normal along the motion) are ignored, so a robot touching a wall can back away.
  SweepResult sweep(const Vec2& from, const Vec2& to) const;

  // True if the footprint at p overlaps an obstacle (penetration beyond `tolerance` m).
  bool overlaps(const Vec2& p, double tolerance = 1e-4) const;

  // One btCollisionWorld::rayTest in the laser's plane: the naive baseline for the benchmark and a
  // cross-check of RayCaster2D in the tests. Returns +inf if nothing is hit within max_range.
  double rayTest(double ox, double oy, double dx, double dy, double max_range) const;

  size_t objectCount() const { return objects_.size(); }

 private:
  double height_;
  double robot_radius_;
  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btDbvtBroadphase> broadphase_;
  std::unique_ptr<btCollisionWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> objects_;
  std::unique_ptr<btSphereShape> footprint_;
};

}  // namespace bullet_sim
