// Planar geometry shared by the whole hybrid_slam stack (laser_features, ekf_local_map, pomdp_topo):
// angles, poses with the compounding operators of Smith, Self & Cheeseman, and infinite lines in the
// (alpha, r) model of Arras & Siegwart, with the Jacobians an EKF needs.
//
// Conventions (DESIGN.md): angles in radians normalized to (-pi, pi]; covariances are full matrices;
// a line is the set of points p with  n(alpha) . p = r,  i.e.  rho cos(phi - alpha) - r = 0  in polar
// coordinates, with r >= 0 (n points from the frame origin towards the line).
//
// ROS-free: Eigen and the standard library only.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>  // inverse() and determinant() of the small matrices

#include <cmath>

namespace laser_features {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

using Matrix23d = Eigen::Matrix<double, 2, 3>;
using Matrix24d = Eigen::Matrix<double, 2, 4>;

// ---------------------------------------------------------------------------------------------
// Angles

/// Wraps an angle to (-pi, pi]. A non-finite input gives NaN.
inline double normalizeAngle(double angle) {
  // Sums and differences of normalized angles need at most one turn: avoid the division.
  if (angle > kPi) {
    angle -= kTwoPi;
  } else if (angle <= -kPi) {
    angle += kTwoPi;
  }
  if (angle > -kPi && angle <= kPi) return angle;
  const double wrapped = std::remainder(angle, kTwoPi);  // in [-pi, pi]
  return wrapped <= -kPi ? wrapped + kTwoPi : wrapped;
}

/// Unit vector at `angle`.
inline Eigen::Vector2d unitVector(double angle) { return {std::cos(angle), std::sin(angle)}; }

/// z-component of the cross product a x b (twice the signed area of the triangle 0, a, b).
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// ---------------------------------------------------------------------------------------------
// Poses (Smith, Self & Cheeseman 1990, "Estimating uncertain spatial relationships in robotics":
// compounding  a (+) b  and inverse  (-)a, with their Jacobians)

/// Pose of a frame B in a frame A: B's origin at (x, y) and B's x-axis at angle theta, in A.
struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  Eigen::Vector2d translation() const { return {x, y}; }
};

/// a (+) b: the pose of C in A, given B in A (`a`) and C in B (`b`).
/// J_a = d(a (+) b)/da and J_b = d(a (+) b)/db (3x3 each), when requested.
Pose2D compose(const Pose2D& a, const Pose2D& b, Eigen::Matrix3d* J_a = nullptr,
               Eigen::Matrix3d* J_b = nullptr);

/// (-)a: the pose of A in B, given B in A. J = d((-)a)/da when requested.
Pose2D inverse(const Pose2D& a, Eigen::Matrix3d* J = nullptr);

/// A point given in `frame` (whose pose is given in the parent frame) expressed in the parent frame:
/// p_parent = R(theta) p + t.  J_pose = dp_parent/d(x, y, theta) when requested.
Eigen::Vector2d transformPoint(const Pose2D& frame, const Eigen::Vector2d& p_in_frame,
                               Matrix23d* J_pose = nullptr);

// ---------------------------------------------------------------------------------------------
// Lines (Arras & Siegwart 1997, "Feature extraction and scene interpretation for map-based
// navigation and map building": the (alpha, r) line model with its 2x2 covariance)

/// An infinite line  x cos(alpha) + y sin(alpha) = r  with its covariance over (alpha, r).
struct Line {
  double alpha = 0.0;
  double r = 0.0;
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();

  /// Unit normal, from the origin towards the line when r > 0.
  Eigen::Vector2d normal() const { return unitVector(alpha); }
  /// Unit direction along the line: the normal turned by +90 degrees (counter-clockwise as seen
  /// from the origin).
  Eigen::Vector2d direction() const { return {-std::sin(alpha), std::cos(alpha)}; }
  Eigen::Vector2d params() const { return {alpha, r}; }
};

/// Brings a line to the canonical form r >= 0, alpha in (-pi, pi]: when r < 0 the same line is
/// (alpha + pi, -r). Updates the covariance accordingly. J = d(canonical)/d(input), which is
/// diag(1, -1) after a flip and the identity otherwise. Returns true when the sign was flipped.
bool canonicalize(Line* line, Eigen::Matrix2d* J = nullptr);

/// The line through two distinct points, canonical, with zero covariance.
Line lineThroughPoints(const Eigen::Vector2d& p, const Eigen::Vector2d& q);

/// Expresses a line given in the world frame in a frame whose pose in the world is `frame_in_world`
/// (e.g. the robot): the EKF measurement prediction
///     h = (alpha - theta,  r - x cos(alpha) - y sin(alpha)),
/// canonicalized (sign flip when the new r < 0). The covariance is propagated through J_line only
/// (add J_pose P J_pose^T for the pose uncertainty). Jacobians when requested:
/// J_line = dh/d(alpha, r) (2x2), J_pose = dh/d(x, y, theta) (2x3), both including the flip.
Line transformLineToFrame(const Line& line_in_world, const Pose2D& frame_in_world,
                          Eigen::Matrix2d* J_line = nullptr, Matrix23d* J_pose = nullptr);

/// The inverse of transformLineToFrame: a line measured in a frame whose pose in the world is
/// `frame_in_world`, expressed in the world (alpha_w = alpha + theta, r_w = r + x cos(alpha_w) +
/// y sin(alpha_w), canonicalized). Same Jacobian and covariance conventions.
Line transformLineFromFrame(const Line& line_in_frame, const Pose2D& frame_in_world,
                            Eigen::Matrix2d* J_line = nullptr, Matrix23d* J_pose = nullptr);

/// (alpha_a - alpha_b, r_a - r_b) with the angle difference wrapped to (-pi, pi], taken with the
/// representation of b, (alpha_b, r_b) or (alpha_b + pi, -r_b), that is closer to a. The second
/// representation matters for lines passing near the origin, whose alpha jumps by pi when r
/// changes sign.
Eigen::Vector2d lineDifference(const Line& a, const Line& b);

/// Squared Mahalanobis distance of two independent line estimates,
///     d^T (C_a + C_b)^-1 d  with  d = lineDifference(a, b),
/// chi^2-distributed with 2 degrees of freedom when both estimate the same line.
/// +infinity when C_a + C_b is not positive definite.
double lineMahalanobisSq(const Line& a, const Line& b);

/// Angle between two (undirected) lines, in [0, pi/2].
double angleBetweenLines(const Line& a, const Line& b);

/// Signed distance of a point from a line: positive on the side away from the origin
/// (n . p - r).
inline double signedDistanceToLine(const Line& line, const Eigen::Vector2d& p) {
  return line.normal().dot(p) - line.r;
}

/// A line in Hesse normal form (n . p = r) with its normal computed once, for loops that measure
/// many points against the same line.
struct HesseLine {
  explicit HesseLine(const Line& line) : normal(line.normal()), r(line.r) {}
  /// Same as signedDistanceToLine.
  double distance(const Eigen::Vector2d& p) const { return normal.dot(p) - r; }

  Eigen::Vector2d normal;
  double r;
};

/// Orthogonal projection of a point onto a line.
inline Eigen::Vector2d projectOntoLine(const Line& line, const Eigen::Vector2d& p) {
  const Eigen::Vector2d n = line.normal();
  return p - (n.dot(p) - line.r) * n;
}

/// Range at which a ray from the origin at `bearing` meets the line; +infinity when the ray is
/// parallel to the line or points away from it.
double rangeToLine(const Line& line, double bearing);

/// Intersection point of two lines. Returns false (and leaves the outputs untouched) when the lines
/// are parallel (|sin(alpha_b - alpha_a)| < min_sin). J = dp/d(alpha_a, r_a, alpha_b, r_b) (2x4),
/// from implicit differentiation of  n_a . p = r_a,  n_b . p = r_b.
bool intersectLines(const Line& a, const Line& b, Eigen::Vector2d* p, Matrix24d* J = nullptr,
                    double min_sin = 1e-9);

}  // namespace laser_features
