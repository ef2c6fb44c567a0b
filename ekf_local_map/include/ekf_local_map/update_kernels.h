// The O(n^2 k) and O(n k^2) kernels of the EKF's stacked update (Tomatis et al. 2001, eqs. 15-17),
// on the raw column-major storage of StochasticMap: P symmetric in lower storage, W the gain's
// columns. Written once on a SIMD vector type and instantiated portable (2 doubles: SSE2 / NEON) and,
// on x86-64, AVX2 + FMA, chosen at run time (no -march flag: a build runs on any x86-64 CPU).
//
// ROS-free, no allocation.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ekf_local_map {

/// Rows the kernels may read and write (W) beyond the state size, so that no row needs a scalar
/// tail: W needs this many rows below the state, kept zero.
constexpr std::ptrdiff_t kUpdateKernelRowPadding = 16;

struct UpdateKernels {
  /// W(:, c) = P H_c^T for one match's two columns w0, w1 (eq. 15): H with a robot block (2x3, hr
  /// row-major) and a line block at state index l (2x2, hl row-major); P (n x n, leading
  /// dimension ldp) symmetric in lower storage. O(n) instead of a dense P H^T.
  void (*gain_columns)(const double* P, std::ptrdiff_t ldp, std::ptrdiff_t n, std::ptrdiff_t l, const double* hr,
                       const double* hl, double* w0, double* w1);
  /// In place V = W L^-T (eq. 15 with S = L L^T; Lm lower m x m, inv_diag its inverted diagonal)
  /// and x += V y (eq. 16 with y = L^-1 nu); W is n x m (leading dimension ldw) with
  /// kUpdateKernelRowPadding rows beyond n, zero or finite.
  void (*solve_and_shift)(double* W, std::ptrdiff_t ldw, const double* Lm, std::ptrdiff_t ldl, const double* inv_diag,
                          const double* y, double* x, std::ptrdiff_t n, std::ptrdiff_t m);
  /// The lower triangle of P -= X X^T (eq. 17 as P - V V^T); X is n x m (leading dimension ldx)
  /// with kUpdateKernelRowPadding rows beyond n.
  void (*rank_update_lower)(double* P, std::ptrdiff_t ldp, const double* X, std::ptrdiff_t ldx, std::ptrdiff_t n,
                            std::ptrdiff_t m);
};

/// The kernels in use (process-wide).
const UpdateKernels& activeUpdateKernels();

/// Which instruction set the kernels use: portable (SSE2 / NEON width), or AVX2 + FMA on x86-64
/// CPUs that have it (chosen at run time, the default when available). The results agree up to
/// floating-point rounding. For tests and benchmarks; process-wide.
enum class UpdateKernelIsa : uint8_t { kPortable, kAvx2Fma };
UpdateKernelIsa updateKernelIsa();
/// False, changing nothing, when this CPU (or build) lacks the instruction set.
bool setUpdateKernelIsa(UpdateKernelIsa isa);

}  // namespace ekf_local_map
