// Fast exact 2D ray casting against the world for the simulated laser.
//
// Every wall, box and pillar is a vertical extrusion and the laser scans a horizontal plane, so the
// exact ray test is 2D: box outlines become segments, pillars circles. They are leaves of Bullet's own
// dynamic AABB tree (btDbvt); a ray walks the tree near-child-first and shrinks its far limit at every
// hit, so it visits O(log n) nodes. Nothing is allocated per ray.
#pragma once

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <cstddef>
#include <vector>

#include "bullet_sim/world.h"

namespace bullet_sim {

class RayCaster2D {
 public:
  explicit RayCaster2D(const World& world);
  RayCaster2D(const RayCaster2D&) = delete;
  RayCaster2D& operator=(const RayCaster2D&) = delete;

  // Distance from (ox, oy) along the unit direction (dx, dy) to the first obstacle surface, or
  // +infinity if there is none closer than max_range. Thread-safe (const, no shared scratch).
  // `hit`, when given, receives the index of the primitive hit (unchanged when nothing is hit).
  double cast(double ox, double oy, double dx, double dy, double max_range, size_t* hit = nullptr) const;

  // `count` rays from (ox, oy) at angles start + i * increment (rad, world frame); writes the exact
  // distances (or +inf) to out[0..count).
  void castFan(double ox, double oy, double start, double increment, size_t count, double max_range, float* out) const;

  // A box face (segment a-b, radius 0) or a pillar (circle of centre a): what the laser can hit.
  struct Primitive {
    double ax, ay, bx, by, radius;
  };
  size_t primitiveCount() const { return primitives_.size(); }
  const Primitive& primitive(size_t i) const { return primitives_[i]; }
  int treeDepth() const { return depth_; }

 private:
  static constexpr int kMaxStack = 256;

  std::vector<Primitive> primitives_;
  btDbvt tree_;
  int depth_ = 0;
};

}  // namespace bullet_sim
