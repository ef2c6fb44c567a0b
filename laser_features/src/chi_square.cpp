#include "laser_features/chi_square.h"

#include <cmath>
#include <limits>

namespace laser_features {

double normalQuantile(double p) {
  if (!(p > 0.0 && p < 1.0)) return std::numeric_limits<double>::quiet_NaN();
  // P. J. Acklam's coefficients: a rational approximation in the central region, another in the tails.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02,  -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01,  -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00,  2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  if (p < kLow) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - kLow) return -normalQuantile(1.0 - p);
  const double q = p - 0.5;
  const double r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

double chiSquareQuantile(double p, int dof) {
  if (!(p > 0.0 && p < 1.0) || dof < 1) return std::numeric_limits<double>::quiet_NaN();
  if (dof == 2) return -2.0 * std::log(1.0 - p);  // the exponential distribution with mean 2
  // Wilson & Hilferty (1931): (X / k)^(1/3) is nearly normal with mean 1 - 2/(9k), variance 2/(9k).
  const double k = dof;
  const double v = 2.0 / (9.0 * k);
  const double t = 1.0 - v + normalQuantile(p) * std::sqrt(v);
  return k * t * t * t;
}

}  // namespace laser_features
