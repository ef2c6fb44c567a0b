#include "laser_features/line_fit.h"

#include <cmath>

namespace laser_features {

WeightedLineFit::WeightedLineFit(double range_sigma, double range_sigma_per_meter, double bearing_sigma)
    : range_sigma_(range_sigma), range_sigma_per_meter_(range_sigma_per_meter), bearing_sigma_(bearing_sigma) {
  // Arras & Siegwart weight the points with 1/sigma_rho^2: constant unless the noise grows with range.
  constant_weight_ = range_sigma_per_meter_ == 0.0 ? 1.0 / (range_sigma_ * range_sigma_) : 0.0;
}

// Weighted total least squares line fit with first-order covariance propagation.
//
// Fit (Arras & Siegwart 1997, the weighted (alpha, r) estimate): with weights w_i = 1/sigma_rho_i^2,
// the weighted centroid (xm, ym) and the centred second moments Sxx, Syy, Sxy,
//     alpha = 1/2 atan2(-2 Sxy, Syy - Sxx),     r = xm cos(alpha) + ym sin(alpha),
// then (alpha, r) -> (alpha + pi, -r) when r < 0.
//
// Covariance (the first-order propagation of Arras & Siegwart 1997, C_AR = sum_i J_i C_i J_i^T, cf.
// Pfister et al. 2003, "Weighted line fitting algorithms for mobile robot map building and efficient
// data representation", ICRA): the fit solves g(alpha, r; p) = 0 with
//     g = [ sum_i w_i d_i s_i ,  sum_i w_i d_i ],  d_i = n.p_i - r (residual),  s_i = t.p_i,
// n = (cos a, sin a), t = (-sin a, cos a). Implicit differentiation gives d(alpha, r)/dp_i = -G^-1 B_i,
//     G = [[sum w (s^2 - d^2), -sum w s], [sum w s, -sum w]],   B_i = w_i [ (s_i n + d_i t)^T ; n^T ],
// and C = G^-1 (sum_i B_i M_i B_i^T) G^-T with M_i the Cartesian covariance of point i from the range
// and bearing noise, M_i = sigma_rho^2 u u^T + sigma_theta^2 rho^2 v v^T (u the beam direction, v its
// normal).
bool WeightedLineFit::fit(const ScanPoints& points, size_t begin, size_t end, const std::vector<uint8_t>* ignored,
                          Line* line, uint32_t* num_points) const {
  const auto take = [&](size_t i) {
    return points[i].status == BeamStatus::kValid && !(ignored && (*ignored)[i]);
  };
  // Pass 1: weighted centroid and scatter, shifted to the first point for numerical stability.
  const Eigen::Vector2d shift = points[points.wrap(begin)].p;
  double W = 0.0, Sx = 0.0, Sy = 0.0, Sxx = 0.0, Syy = 0.0, Sxy = 0.0;
  uint32_t count = 0;
  points.forEachIndex(begin, end, [&](size_t i, size_t) {
    if (!take(i)) return;
    const BeamPoint& point = points[i];
    const double w = weight(point.range);
    const double dx = point.p.x() - shift.x();
    const double dy = point.p.y() - shift.y();
    W += w;
    Sx += w * dx;
    Sy += w * dy;
    Sxx += w * dx * dx;
    Syy += w * dy * dy;
    Sxy += w * dx * dy;
    ++count;
  });
  if (count < 2 || !(W > 0.0)) return false;
  const double mx = Sx / W, my = Sy / W;
  const double cxx = Sxx / W - mx * mx;
  const double cyy = Syy / W - my * my;
  const double cxy = Sxy / W - mx * my;
  Line result;
  result.alpha = 0.5 * std::atan2(-2.0 * cxy, cyy - cxx);
  const Eigen::Vector2d fitted_normal = unitVector(result.alpha);
  result.r = fitted_normal.dot(shift + Eigen::Vector2d(mx, my));
  const bool flipped = canonicalize(&result);

  // Pass 2: covariance. Per point only rho and the bearing are needed:
  // n.u = cos(phi - alpha), t.u = sin(phi - alpha), n.v = -t.u, t.v = n.u.
  const double ca = flipped ? -fitted_normal.x() : fitted_normal.x();  // a flip turns the normal by pi
  const double sa = flipped ? -fitted_normal.y() : fitted_normal.y();
  const double sigma_theta2 = bearing_sigma_ * bearing_sigma_;
  double G00 = 0.0, Gs = 0.0, H00 = 0.0, H01 = 0.0, H11 = 0.0;
  points.forEachIndex(begin, end, [&](size_t i, size_t) {
    if (!take(i)) return;
    const Eigen::Vector2d& u = points.unit(i);
    const double nu = ca * u.x() + sa * u.y();
    const double tu = -sa * u.x() + ca * u.y();
    const double rho = points[i].range;
    const double s = rho * tu;
    const double d = rho * nu - result.r;
    const double w = weight(rho);  // = 1 / var_rho, so w^2 var_rho = w
    const double w2_var_across_beam = w * w * sigma_theta2 * rho * rho;  // bearing noise, in m^2
    // a = s n + d t and n, in the (u, v) basis.
    const double au = s * nu + d * tu;
    const double av = -s * tu + d * nu;
    const double n_u = nu, n_v = -tu;
    G00 += w * (s * s - d * d);
    Gs += w * s;
    H00 += w * au * au + w2_var_across_beam * av * av;
    H01 += w * au * n_u + w2_var_across_beam * av * n_v;
    H11 += w * n_u * n_u + w2_var_across_beam * n_v * n_v;
  });
  Eigen::Matrix2d G;
  G << G00, -Gs,  //
      Gs, -W;
  const double det = G.determinant();
  if (!std::isfinite(det) || std::abs(det) < 1e-300) return false;
  Eigen::Matrix2d H;
  H << H00, H01,  //
      H01, H11;
  const Eigen::Matrix2d G_inv = G.inverse();
  Eigen::Matrix2d cov = G_inv * H * G_inv.transpose();
  cov = 0.5 * (cov + cov.transpose());
  if (!cov.allFinite() || !(cov(0, 0) > 0.0) || !(cov(1, 1) > 0.0)) return false;
  result.cov = cov;
  *line = result;
  *num_points = count;
  return true;
}

}  // namespace laser_features
