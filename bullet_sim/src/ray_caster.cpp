#include "bullet_sim/ray_caster.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace bullet_sim {
namespace {

int depthOf(const btDbvtNode* node) {
  if (!node) return 0;
  if (node->isleaf()) return 1;
  return 1 + std::max(depthOf(node->childs[0]), depthOf(node->childs[1]));
}

// Entry distance of the ray into a node's box (2D slab test), +inf if it misses within t_max.
inline double slabEntry(const btDbvtVolume& v, double ox, double oy, double inv_dx, double inv_dy, double t_max) {
  double t0 = (v.Mins().x() - ox) * inv_dx;
  double t1 = (v.Maxs().x() - ox) * inv_dx;
  if (t0 > t1) std::swap(t0, t1);
  double u0 = (v.Mins().y() - oy) * inv_dy;
  double u1 = (v.Maxs().y() - oy) * inv_dy;
  if (u0 > u1) std::swap(u0, u1);
  const double enter = std::max(std::max(t0, u0), 0.0);
  const double leave = std::min(std::min(t1, u1), t_max);
  return enter <= leave ? enter : std::numeric_limits<double>::infinity();
}

}  // namespace

RayCaster2D::RayCaster2D(const World& world) {
  for (const OrientedBox& b : world.solidBoxes()) {
    const double c = std::cos(b.yaw), s = std::sin(b.yaw);
    double cx[4], cy[4];
    const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
    for (int k = 0; k < 4; ++k) {
      cx[k] = b.center.x + c * sx[k] * b.half_x - s * sy[k] * b.half_y;
      cy[k] = b.center.y + s * sx[k] * b.half_x + c * sy[k] * b.half_y;
    }
    for (int k = 0; k < 4; ++k) primitives_.push_back({cx[k], cy[k], cx[(k + 1) % 4], cy[(k + 1) % 4], 0.0});
  }
  for (const Cylinder& c : world.cylinders) primitives_.push_back({c.center.x, c.center.y, 0.0, 0.0, c.radius});

  for (size_t i = 0; i < primitives_.size(); ++i) {
    const Primitive& p = primitives_[i];
    // Padded so that float rounding of the tree's bounds never loses a hit at a segment's end.
    constexpr double pad = 1e-4;
    btVector3 lo, hi;
    if (p.radius > 0.0) {
      lo = btVector3(p.ax - p.radius - pad, p.ay - p.radius - pad, -1);
      hi = btVector3(p.ax + p.radius + pad, p.ay + p.radius + pad, 1);
    } else {
      lo = btVector3(std::min(p.ax, p.bx) - pad, std::min(p.ay, p.by) - pad, -1);
      hi = btVector3(std::max(p.ax, p.bx) + pad, std::max(p.ay, p.by) + pad, 1);
    }
    tree_.insert(btDbvtVolume::FromMM(lo, hi), reinterpret_cast<void*>(static_cast<std::intptr_t>(i)));
  }
  tree_.optimizeTopDown();
  depth_ = depthOf(tree_.m_root);
  if (depth_ >= kMaxStack) throw std::runtime_error("RayCaster2D: obstacle tree too deep");
}

double RayCaster2D::cast(double ox, double oy, double dx, double dy, double max_range, size_t* hit_index) const {
  const double inf = std::numeric_limits<double>::infinity();
  double best = max_range;
  bool hit = false;
  if (!tree_.m_root) return inf;
  // Huge but finite inverses keep the slab test free of 0 * inf.
  const double inv_dx = dx != 0.0 ? 1.0 / dx : 1e300;
  const double inv_dy = dy != 0.0 ? 1.0 / dy : 1e300;

  struct Entry {
    const btDbvtNode* node;
    double t;
  };
  Entry stack[kMaxStack];
  int top = 0;
  const double t_root = slabEntry(tree_.m_root->volume, ox, oy, inv_dx, inv_dy, best);
  if (t_root == inf) return inf;
  stack[top++] = {tree_.m_root, t_root};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.t > best) continue;
    const btDbvtNode* node = e.node;
    if (node->isleaf()) {
      const size_t index = static_cast<size_t>(reinterpret_cast<std::intptr_t>(node->data));
      const Primitive& p = primitives_[index];
      if (p.radius > 0.0) {
        // |o + t d - c|^2 = r^2, nearest root with t >= 0
        const double fx = ox - p.ax, fy = oy - p.ay;
        const double b = fx * dx + fy * dy;
        const double c = fx * fx + fy * fy - p.radius * p.radius;
        const double disc = b * b - c;
        if (disc >= 0.0) {
          const double t = -b - std::sqrt(disc);
          if (t >= 0.0 && t < best) {
            best = t;
            hit = true;
            if (hit_index) *hit_index = index;
          }
        }
      } else {
        // o + t d = a + s (b - a), 0 <= s <= 1
        const double ex = p.bx - p.ax, ey = p.by - p.ay;
        const double denom = dx * ey - dy * ex;
        if (denom != 0.0) {
          const double wx = p.ax - ox, wy = p.ay - oy;
          const double t = (wx * ey - wy * ex) / denom;
          const double s = (wx * dy - wy * dx) / denom;
          if (t >= 0.0 && t < best && s >= 0.0 && s <= 1.0) {
            best = t;
            hit = true;
            if (hit_index) *hit_index = index;
          }
        }
      }
      continue;
    }
    const btDbvtNode* c0 = node->childs[0];
    const btDbvtNode* c1 = node->childs[1];
    double t0 = slabEntry(c0->volume, ox, oy, inv_dx, inv_dy, best);
    double t1 = slabEntry(c1->volume, ox, oy, inv_dx, inv_dy, best);
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(c0, c1);
    }
    // Push the far child first so the near one is visited first.
    if (t1 != inf) stack[top++] = {c1, t1};
    if (t0 != inf) stack[top++] = {c0, t0};
  }
  return hit ? best : inf;
}

void RayCaster2D::castFan(double ox, double oy, double start, double increment, size_t count, double max_range,
                          float* out) const {
  // Rotate the direction incrementally (one sin/cos pair per fan); re-seed every 64 beams against drift.
  const double cs = std::cos(increment), sn = std::sin(increment);
  double dx = 0.0, dy = 0.0;
  for (size_t i = 0; i < count; ++i) {
    if ((i & 63u) == 0) {
      const double a = start + static_cast<double>(i) * increment;
      dx = std::cos(a);
      dy = std::sin(a);
    } else {
      const double nx = dx * cs - dy * sn;
      dy = dx * sn + dy * cs;
      dx = nx;
    }
    out[i] = static_cast<float>(cast(ox, oy, dx, dy, max_range));
  }
}

}  // namespace bullet_sim
