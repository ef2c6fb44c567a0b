// Quantiles of the chi-square distribution, for validation gates and consistency bands.
#pragma once

namespace laser_features {

/// The value below which a chi-square variable with `dof` degrees of freedom falls with
/// probability `p` (0 < p < 1). Exact for dof = 2 (-2 ln(1 - p)); otherwise the Wilson–Hilferty
/// cube-root approximation, within 1% for dof >= 3 and p in [0.01, 0.999] (2% for dof = 1).
double chiSquareQuantile(double p, int dof);

/// Quantile of the standard normal distribution (Acklam's rational approximation, relative error
/// below 1.2e-9).
double normalQuantile(double p);

}  // namespace laser_features
