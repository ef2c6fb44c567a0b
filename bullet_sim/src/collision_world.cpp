#include "bullet_sim/collision_world.h"

#include <cmath>
#include <limits>

namespace bullet_sim {
namespace {

// Closest hit of a sweep, ignoring contacts the motion moves away from.
struct OncomingSweepCallback : public btCollisionWorld::ClosestConvexResultCallback {
  OncomingSweepCallback(const btVector3& from, const btVector3& to)
      : ClosestConvexResultCallback(from, to), motion_(to - from) {}
  btScalar addSingleResult(btCollisionWorld::LocalConvexResult& r, bool normal_in_world) override {
    const btVector3 n = normal_in_world ? r.m_hitNormalLocal
                                        : r.m_hitCollisionObject->getWorldTransform().getBasis() * r.m_hitNormalLocal;
    if (n.dot(motion_) >= 0.0) return m_closestHitFraction;  // leaving or sliding along: not a contact
    return ClosestConvexResultCallback::addSingleResult(r, normal_in_world);
  }
  btVector3 motion_;
};

struct PenetrationCallback : public btCollisionWorld::ContactResultCallback {
  explicit PenetrationCallback(double tolerance) : tolerance_(tolerance) {}
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int, const btCollisionObjectWrapper*,
                           int, int) override {
    if (cp.getDistance() < -tolerance_) hit = true;
    return 0;
  }
  double tolerance_;
  bool hit = false;
};

}  // namespace

CollisionWorld::CollisionWorld(const World& world, double robot_radius)
    : height_(world.wall_height), robot_radius_(robot_radius) {
  config_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  world_ = std::make_unique<btCollisionWorld>(dispatcher_.get(), broadphase_.get(), config_.get());

  auto add = [&](std::unique_ptr<btCollisionShape> shape, const Vec2& c, double yaw) {
    auto object = std::make_unique<btCollisionObject>();
    btTransform t;
    t.setIdentity();
    t.setOrigin(btVector3(c.x, c.y, height_ / 2));
    t.setRotation(btQuaternion(btVector3(0, 0, 1), yaw));
    object->setWorldTransform(t);
    object->setCollisionShape(shape.get());
    world_->addCollisionObject(object.get());
    shapes_.push_back(std::move(shape));
    objects_.push_back(std::move(object));
  };
  // Zero collision margins: the shapes are exactly the world's (Bullet's default 4 cm margin rounds
  // box edges and shifts ray hits by up to a few centimetres).
  for (const OrientedBox& b : world.solidBoxes()) {
    auto box = std::make_unique<btBoxShape>(btVector3(b.half_x, b.half_y, height_ / 2));
    box->setMargin(0.0);
    add(std::move(box), b.center, b.yaw);
  }
  for (const Cylinder& c : world.cylinders) {
    auto cylinder = std::make_unique<btCylinderShapeZ>(btVector3(c.radius, c.radius, height_ / 2));
    cylinder->setMargin(0.0);
    add(std::move(cylinder), c.center, 0.0);
  }
  world_->updateAabbs();
  // A sphere at mid-height cuts the vertical obstacles exactly like the round footprint does.
  footprint_ = std::make_unique<btSphereShape>(robot_radius);
}

CollisionWorld::~CollisionWorld() {
  for (auto& o : objects_) world_->removeCollisionObject(o.get());
}

SweepResult CollisionWorld::sweep(const Vec2& from, const Vec2& to) const {
  SweepResult out;
  const btVector3 a(from.x, from.y, height_ / 2), b(to.x, to.y, height_ / 2);
  if ((b - a).length2() == 0.0) return out;
  btTransform ta, tb;
  ta.setIdentity();
  tb.setIdentity();
  ta.setOrigin(a);
  tb.setOrigin(b);
  OncomingSweepCallback cb(a, b);
  world_->convexSweepTest(footprint_.get(), ta, tb, cb, 0.0);
  if (cb.hasHit()) {
    out.contact = true;
    out.fraction = cb.m_closestHitFraction;
  }
  return out;
}

bool CollisionWorld::overlaps(const Vec2& p, double tolerance) const {
  btCollisionObject probe;
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(p.x, p.y, height_ / 2));
  probe.setWorldTransform(t);
  probe.setCollisionShape(footprint_.get());
  PenetrationCallback cb(tolerance);
  world_->contactTest(&probe, cb);
  return cb.hit;
}

double CollisionWorld::rayTest(double ox, double oy, double dx, double dy, double max_range) const {
  const btVector3 from(ox, oy, height_ / 2), to(ox + dx * max_range, oy + dy * max_range, height_ / 2);
  btCollisionWorld::ClosestRayResultCallback cb(from, to);
  world_->rayTest(from, to, cb);
  return cb.hasHit() ? cb.m_closestHitFraction * max_range : std::numeric_limits<double>::infinity();
}

}  // namespace bullet_sim
