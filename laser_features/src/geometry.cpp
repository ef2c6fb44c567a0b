#include "laser_features/geometry.h"

#include <algorithm>
#include <limits>

namespace laser_features {

Pose2D compose(const Pose2D& a, const Pose2D& b, Eigen::Matrix3d* J_a, Eigen::Matrix3d* J_b) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  const Pose2D ab{a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, normalizeAngle(a.theta + b.theta)};
  if (J_a) {
    *J_a << 1.0, 0.0, -s * b.x - c * b.y,  //
        0.0, 1.0, c * b.x - s * b.y,       //
        0.0, 0.0, 1.0;
  }
  if (J_b) {
    *J_b << c, -s, 0.0,  //
        s, c, 0.0,       //
        0.0, 0.0, 1.0;
  }
  return ab;
}

Pose2D inverse(const Pose2D& a, Eigen::Matrix3d* J) {
  const double c = std::cos(a.theta);
  const double s = std::sin(a.theta);
  const Pose2D inv{-c * a.x - s * a.y, s * a.x - c * a.y, normalizeAngle(-a.theta)};
  if (J) {
    *J << -c, -s, s * a.x - c * a.y,  //
        s, -c, c * a.x + s * a.y,     //
        0.0, 0.0, -1.0;
  }
  return inv;
}

Eigen::Vector2d transformPoint(const Pose2D& frame, const Eigen::Vector2d& p, Matrix23d* J_pose) {
  const double c = std::cos(frame.theta);
  const double s = std::sin(frame.theta);
  if (J_pose) {
    *J_pose << 1.0, 0.0, -s * p.x() - c * p.y(),  //
        0.0, 1.0, c * p.x() - s * p.y();
  }
  return {frame.x + c * p.x() - s * p.y(), frame.y + s * p.x() + c * p.y()};
}

bool canonicalize(Line* line, Eigen::Matrix2d* J) {
  const bool flip = line->r < 0.0;
  if (flip) {
    // (alpha, r) and (alpha + pi, -r) are the same line; d(canonical)/d(input) = diag(1, -1).
    line->alpha += kPi;
    line->r = -line->r;
    line->cov(0, 1) = -line->cov(0, 1);
    line->cov(1, 0) = -line->cov(1, 0);
  }
  line->alpha = normalizeAngle(line->alpha);
  if (J) *J << 1.0, 0.0, 0.0, flip ? -1.0 : 1.0;
  return flip;
}

Line lineThroughPoints(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  const Eigen::Vector2d d = q - p;
  Line line;
  line.alpha = std::atan2(d.x(), -d.y());  // normal = direction turned by -90 degrees
  line.r = line.normal().dot(p);
  canonicalize(&line);
  return line;
}

Line transformLineToFrame(const Line& world, const Pose2D& frame, Eigen::Matrix2d* J_line,
                          Matrix23d* J_pose) {
  const double c = std::cos(world.alpha);
  const double s = std::sin(world.alpha);
  Line local;
  local.alpha = world.alpha - frame.theta;
  local.r = world.r - frame.x * c - frame.y * s;
  Eigen::Matrix2d Jl;
  Jl << 1.0, 0.0,  //
      frame.x * s - frame.y * c, 1.0;
  Matrix23d Jp;
  Jp << 0.0, 0.0, -1.0,  //
      -c, -s, 0.0;
  Eigen::Matrix2d J_flip;
  canonicalize(&local, &J_flip);  // covariance is still zero here; set below
  Jl = J_flip * Jl;
  Jp = J_flip * Jp;
  local.cov = Jl * world.cov * Jl.transpose();
  if (J_line) *J_line = Jl;
  if (J_pose) *J_pose = Jp;
  return local;
}

Line transformLineFromFrame(const Line& local, const Pose2D& frame, Eigen::Matrix2d* J_line,
                            Matrix23d* J_pose) {
  const double alpha_w = local.alpha + frame.theta;
  const double c = std::cos(alpha_w);
  const double s = std::sin(alpha_w);
  const double dr_dalpha = -frame.x * s + frame.y * c;
  Line world;
  world.alpha = alpha_w;
  world.r = local.r + frame.x * c + frame.y * s;
  Eigen::Matrix2d Jl;
  Jl << 1.0, 0.0,  //
      dr_dalpha, 1.0;
  Matrix23d Jp;
  Jp << 0.0, 0.0, 1.0,  //
      c, s, dr_dalpha;
  Eigen::Matrix2d J_flip;
  canonicalize(&world, &J_flip);
  Jl = J_flip * Jl;
  Jp = J_flip * Jp;
  world.cov = Jl * local.cov * Jl.transpose();
  if (J_line) *J_line = Jl;
  if (J_pose) *J_pose = Jp;
  return world;
}

Eigen::Vector2d lineDifference(const Line& a, const Line& b) {
  const Eigen::Vector2d same(normalizeAngle(a.alpha - b.alpha), a.r - b.r);
  const Eigen::Vector2d flipped(normalizeAngle(a.alpha - b.alpha - kPi), a.r + b.r);
  return std::abs(flipped.x()) < std::abs(same.x()) ? flipped : same;
}

double lineMahalanobisSq(const Line& a, const Line& b) {
  const Eigen::Vector2d d = lineDifference(a, b);
  const Eigen::Matrix2d S = a.cov + b.cov;
  const double s01 = 0.5 * (S(0, 1) + S(1, 0));
  const double det = S(0, 0) * S(1, 1) - s01 * s01;
  if (!(det > 0.0) || !(S(0, 0) > 0.0)) return std::numeric_limits<double>::infinity();
  // d^T S^-1 d with the closed-form 2x2 inverse.
  return (d.x() * d.x() * S(1, 1) - 2.0 * d.x() * d.y() * s01 + d.y() * d.y() * S(0, 0)) / det;
}

double angleBetweenLines(const Line& a, const Line& b) {
  const double d = std::abs(normalizeAngle(a.alpha - b.alpha));
  return std::min(d, kPi - d);
}

double rangeToLine(const Line& line, double bearing) {
  const double c = std::cos(bearing - line.alpha);
  if (!(std::abs(c) > 1e-12)) return std::numeric_limits<double>::infinity();
  const double range = line.r / c;
  return range >= 0.0 ? range : std::numeric_limits<double>::infinity();
}

bool intersectLines(const Line& a, const Line& b, Eigen::Vector2d* p, Matrix24d* J, double min_sin) {
  // Solve A p = (r_a, r_b) with the rows of A the two normals; det A = sin(alpha_b - alpha_a).
  const double ca = std::cos(a.alpha), sa = std::sin(a.alpha);
  const double cb = std::cos(b.alpha), sb = std::sin(b.alpha);
  const double det = ca * sb - sa * cb;
  if (!(std::abs(det) >= min_sin)) return false;
  Eigen::Matrix2d A_inv;
  A_inv << sb, -sa,  //
      -cb, ca;
  A_inv /= det;
  const Eigen::Vector2d point = A_inv * Eigen::Vector2d(a.r, b.r);
  if (J) {
    // Differentiating n_a(alpha_a) . p = r_a gives  t_a . p dalpha_a + n_a . dp = dr_a  (t = dn/dalpha),
    // so dp = A^-1 (dr - [t_a . p dalpha_a, t_b . p dalpha_b]).
    const double ta_p = -sa * point.x() + ca * point.y();
    const double tb_p = -sb * point.x() + cb * point.y();
    Matrix24d rhs;
    rhs << -ta_p, 1.0, 0.0, 0.0,  //
        0.0, 0.0, -tb_p, 1.0;
    *J = A_inv * rhs;
  }
  *p = point;
  return true;
}

}  // namespace laser_features
