#include "ekf_local_map/update_kernels.h"

#include <algorithm>
#include <atomic>
#include <cstring>

namespace ekf_local_map {

namespace {

// ---------------------------------------------------------------------------------------------
// The O(n^2 k) and O(n k^2) kernels of the stacked update (eqs. 15-17), written once on a SIMD
// vector type V (GCC/Clang vector extensions; a plain double is the scalar case) and instantiated
// twice: portable (2 doubles, SSE2/NEON) and, on x86-64, AVX2+FMA for CPUs that have it, chosen at
// run time. Only the function attributes differ: no global compiler flag (-march) is involved, so
// a build runs on any x86-64 CPU. P -= V V^T dominates the update (n^2 k multiply-adds), and
// Eigen's generic GEMM path spent more time packing and dispatching than multiplying at these sizes.

#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"  // the AVX vector type appears only inside the AVX2 functions
#define EKF_ALWAYS_INLINE inline __attribute__((always_inline))
using Vec2d = double __attribute__((vector_size(16)));
#else
#define EKF_ALWAYS_INLINE inline
using Vec2d = double;
#endif
#if defined(__GNUC__) && defined(__x86_64__)
#define EKF_LOCAL_MAP_AVX2_KERNELS 1
using Vec4d = double __attribute__((vector_size(32)));
#endif

template <class V>
constexpr std::ptrdiff_t lanes() {
  return std::ptrdiff_t(sizeof(V) / sizeof(double));
}
template <class V>
EKF_ALWAYS_INLINE V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof(V));  // unaligned
  return v;
}
template <class V>
EKF_ALWAYS_INLINE void store(double* p, const V& v) {
  std::memcpy(p, &v, sizeof(V));
}
template <class V>
EKF_ALWAYS_INLINE V splat(double s) {
  if constexpr (lanes<V>() == 1) {
    return s;
  } else {
    V v;
    for (std::ptrdiff_t t = 0; t < lanes<V>(); ++t) v[t] = s;  // one broadcast instruction
    return v;
  }
}

/// W(:, c) = P H_c^T for one match's two columns c0, c0 + 1 (eq. 15), P symmetric in lower storage
/// (column-major, leading dimension ldp), H with a robot block (2x3, hr row-major) and a line block
/// at state index l (2x2, hl row-major): O(n) instead of a dense P H^T.
template <class V>
EKF_ALWAYS_INLINE void gainColumnsImpl(const double* P, std::ptrdiff_t ldp, std::ptrdiff_t n, std::ptrdiff_t l,
                                       const double* hr, const double* hl, double* w0, double* w1) {
  constexpr std::ptrdiff_t L = lanes<V>();
  const double* p0 = P;            // column 0: robot x
  const double* p1 = P + ldp;      // column 1
  const double* p2 = P + 2 * ldp;  // column 2
  const double* pl0 = P + l * ldp;
  const double* pl1 = P + (l + 1) * ldp;
  // Rows 0-2 (the robot block, symmetric) and rows l, l+1 (the line's own block) are done below.
  // Rows 3..l-1: robot columns below the diagonal, line columns read across row l (lower storage).
  for (std::ptrdiff_t i = 3; i < l; ++i) {
    const double a = p0[i], b = p1[i], c = p2[i];
    const double q0 = P[l + i * ldp], q1 = P[l + 1 + i * ldp];  // P(l, i), P(l+1, i)
    w0[i] = a * hr[0] + b * hr[1] + c * hr[2] + q0 * hl[0] + q1 * hl[1];
    w1[i] = a * hr[3] + b * hr[4] + c * hr[5] + q0 * hl[2] + q1 * hl[3];
  }
  // Rows l+2..n-1: every column below the diagonal, contiguous.
  std::ptrdiff_t i = l + 2;
  const V hr0 = splat<V>(hr[0]), hr1 = splat<V>(hr[1]), hr2 = splat<V>(hr[2]);
  const V hr3 = splat<V>(hr[3]), hr4 = splat<V>(hr[4]), hr5 = splat<V>(hr[5]);
  const V hl0 = splat<V>(hl[0]), hl1 = splat<V>(hl[1]), hl2 = splat<V>(hl[2]), hl3 = splat<V>(hl[3]);
  for (; i + L <= n; i += L) {
    const V a = load<V>(p0 + i), b = load<V>(p1 + i), c = load<V>(p2 + i);
    const V q0 = load<V>(pl0 + i), q1 = load<V>(pl1 + i);
    store<V>(w0 + i, a * hr0 + b * hr1 + c * hr2 + q0 * hl0 + q1 * hl1);
    store<V>(w1 + i, a * hr3 + b * hr4 + c * hr5 + q0 * hl2 + q1 * hl3);
  }
  for (; i < n; ++i) {
    const double a = p0[i], b = p1[i], c = p2[i], q0 = pl0[i], q1 = pl1[i];
    w0[i] = a * hr[0] + b * hr[1] + c * hr[2] + q0 * hl[0] + q1 * hl[1];
    w1[i] = a * hr[3] + b * hr[4] + c * hr[5] + q0 * hl[2] + q1 * hl[3];
  }
}

/// In place V = W L^-T (rows independent: forward substitution along each row, eq. 15 with
/// S = L L^T) and x += V y (eq. 16 with y = L^-1 nu). W is n x m (leading dimension ldw, at least
/// kUpdateKernelRowPadding rows beyond n, zero or finite), L lower m x m. Rows are taken 4 vectors at a time so
/// that the substitution's serial chains overlap; the last block runs into the padding rows, and
/// only x's first n entries are written.
template <class V>
EKF_ALWAYS_INLINE void solveAndShiftImpl(double* W, std::ptrdiff_t ldw, const double* Lm, std::ptrdiff_t ldl,
                                         const double* inv_diag, const double* y, double* x, std::ptrdiff_t n,
                                         std::ptrdiff_t m) {
  constexpr std::ptrdiff_t L = lanes<V>();
  static_assert(4 * L <= kUpdateKernelRowPadding, "the last row block must fit in the padding");
  for (std::ptrdiff_t i = 0; i < n; i += 4 * L) {
    V x0{}, x1{}, x2{}, x3{};  // (V y) for the block's rows
    for (std::ptrdiff_t c = 0; c < m; ++c) {
      double* wc = W + c * ldw + i;
      // Two partial sums (even and odd d) per vector: 8 independent multiply-add chains.
      V a0 = load<V>(wc), a1 = load<V>(wc + L), a2 = load<V>(wc + 2 * L), a3 = load<V>(wc + 3 * L);
      V o0{}, o1{}, o2{}, o3{};
      const double* lc = Lm + c;  // row c of L: lc[d * ldl]
      std::ptrdiff_t d = 0;
      for (; d + 1 < c; d += 2) {
        const V l0 = splat<V>(lc[d * ldl]), l1 = splat<V>(lc[(d + 1) * ldl]);
        const double* w0 = W + d * ldw + i;
        const double* w1 = w0 + ldw;
        a0 -= load<V>(w0) * l0; o0 += load<V>(w1) * l1;
        a1 -= load<V>(w0 + L) * l0; o1 += load<V>(w1 + L) * l1;
        a2 -= load<V>(w0 + 2 * L) * l0; o2 += load<V>(w1 + 2 * L) * l1;
        a3 -= load<V>(w0 + 3 * L) * l0; o3 += load<V>(w1 + 3 * L) * l1;
      }
      if (d < c) {
        const V l0 = splat<V>(lc[d * ldl]);
        const double* w0 = W + d * ldw + i;
        a0 -= load<V>(w0) * l0;
        a1 -= load<V>(w0 + L) * l0;
        a2 -= load<V>(w0 + 2 * L) * l0;
        a3 -= load<V>(w0 + 3 * L) * l0;
      }
      const V inv = splat<V>(inv_diag[c]), yc = splat<V>(y[c]);
      a0 = (a0 - o0) * inv; a1 = (a1 - o1) * inv; a2 = (a2 - o2) * inv; a3 = (a3 - o3) * inv;
      store<V>(wc, a0); store<V>(wc + L, a1); store<V>(wc + 2 * L, a2); store<V>(wc + 3 * L, a3);
      x0 += a0 * yc; x1 += a1 * yc; x2 += a2 * yc; x3 += a3 * yc;
    }
    double shift[4 * L];
    store<V>(shift, x0); store<V>(shift + L, x1); store<V>(shift + 2 * L, x2); store<V>(shift + 3 * L, x3);
    const std::ptrdiff_t rows = std::min<std::ptrdiff_t>(4 * L, n - i);
    for (std::ptrdiff_t t = 0; t < rows; ++t) x[i + t] += shift[t];
  }
}

/// The lower triangle of P -= X X^T (eq. 17 as P - V V^T), X n x m (at least kUpdateKernelRowPadding rows
/// beyond n, finite): 4 columns of P at a time, their rows 2 vectors at a time with 8 accumulators
/// in registers. Blocks that reach above the diagonal or beyond row n store only their valid part.
template <class V>
EKF_ALWAYS_INLINE void rankUpdateLowerImpl(double* P, std::ptrdiff_t ldp, const double* X, std::ptrdiff_t ldx,
                                           std::ptrdiff_t n, std::ptrdiff_t m) {
  constexpr std::ptrdiff_t L = lanes<V>();
  static_assert(2 * L + 4 <= kUpdateKernelRowPadding, "blocks must fit in the padding");
  for (std::ptrdiff_t j0 = 0; j0 < n; j0 += 4) {
    double* pc[4];
    for (int q = 0; q < 4; ++q) pc[q] = P + (j0 + q) * ldp;
    for (std::ptrdiff_t i = j0; i < n; i += 2 * L) {
      V a0{}, a1{}, a2{}, a3{}, b0{}, b1{}, b2{}, b3{};
      for (std::ptrdiff_t k = 0; k < m; ++k) {
        const double* xk = X + k * ldx;
        const V r0 = load<V>(xk + i), r1 = load<V>(xk + i + L);
        const V c0 = splat<V>(xk[j0]), c1 = splat<V>(xk[j0 + 1]), c2 = splat<V>(xk[j0 + 2]), c3 = splat<V>(xk[j0 + 3]);
        a0 += r0 * c0; b0 += r1 * c0;
        a1 += r0 * c1; b1 += r1 * c1;
        a2 += r0 * c2; b2 += r1 * c2;
        a3 += r0 * c3; b3 += r1 * c3;
      }
      if (i >= j0 + 4 && i + 2 * L <= n) {  // wholly below the diagonal block
        store<V>(pc[0] + i, load<V>(pc[0] + i) - a0); store<V>(pc[0] + i + L, load<V>(pc[0] + i + L) - b0);
        store<V>(pc[1] + i, load<V>(pc[1] + i) - a1); store<V>(pc[1] + i + L, load<V>(pc[1] + i + L) - b1);
        store<V>(pc[2] + i, load<V>(pc[2] + i) - a2); store<V>(pc[2] + i + L, load<V>(pc[2] + i + L) - b2);
        store<V>(pc[3] + i, load<V>(pc[3] + i) - a3); store<V>(pc[3] + i + L, load<V>(pc[3] + i + L) - b3);
      } else {
        double acc[4][2 * L];
        store<V>(acc[0], a0); store<V>(acc[0] + L, b0);
        store<V>(acc[1], a1); store<V>(acc[1] + L, b1);
        store<V>(acc[2], a2); store<V>(acc[2] + L, b2);
        store<V>(acc[3], a3); store<V>(acc[3] + L, b3);
        for (std::ptrdiff_t q = 0; q < 4 && j0 + q < n; ++q) {
          for (std::ptrdiff_t t = std::max<std::ptrdiff_t>(0, j0 + q - i); t < 2 * L && i + t < n; ++t) {
            pc[q][i + t] -= acc[q][t];
          }
        }
      }
    }
  }
}


void gainColumnsPortable(const double* P, std::ptrdiff_t ldp, std::ptrdiff_t n, std::ptrdiff_t l, const double* hr,
                         const double* hl, double* w0, double* w1) {
  gainColumnsImpl<Vec2d>(P, ldp, n, l, hr, hl, w0, w1);
}
void solveAndShiftPortable(double* W, std::ptrdiff_t ldw, const double* Lm, std::ptrdiff_t ldl, const double* inv_diag,
                           const double* y, double* x, std::ptrdiff_t n, std::ptrdiff_t m) {
  solveAndShiftImpl<Vec2d>(W, ldw, Lm, ldl, inv_diag, y, x, n, m);
}
void rankUpdateLowerPortable(double* P, std::ptrdiff_t ldp, const double* X, std::ptrdiff_t ldx, std::ptrdiff_t n,
                             std::ptrdiff_t m) {
  rankUpdateLowerImpl<Vec2d>(P, ldp, X, ldx, n, m);
}
constexpr UpdateKernels kPortableKernels{gainColumnsPortable, solveAndShiftPortable, rankUpdateLowerPortable};

#ifdef EKF_LOCAL_MAP_AVX2_KERNELS
__attribute__((target("avx2,fma"))) void gainColumnsAvx2(const double* P, std::ptrdiff_t ldp, std::ptrdiff_t n,
                                                         std::ptrdiff_t l, const double* hr, const double* hl,
                                                         double* w0, double* w1) {
  gainColumnsImpl<Vec4d>(P, ldp, n, l, hr, hl, w0, w1);
}
__attribute__((target("avx2,fma"))) void solveAndShiftAvx2(double* W, std::ptrdiff_t ldw, const double* Lm,
                                                           std::ptrdiff_t ldl, const double* inv_diag, const double* y,
                                                           double* x, std::ptrdiff_t n, std::ptrdiff_t m) {
  solveAndShiftImpl<Vec4d>(W, ldw, Lm, ldl, inv_diag, y, x, n, m);
}
__attribute__((target("avx2,fma"))) void rankUpdateLowerAvx2(double* P, std::ptrdiff_t ldp, const double* X,
                                                             std::ptrdiff_t ldx, std::ptrdiff_t n, std::ptrdiff_t m) {
  rankUpdateLowerImpl<Vec4d>(P, ldp, X, ldx, n, m);
}
constexpr UpdateKernels kAvx2Kernels{gainColumnsAvx2, solveAndShiftAvx2, rankUpdateLowerAvx2};

bool cpuHasAvx2Fma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}
#else
bool cpuHasAvx2Fma() { return false; }
#endif

const UpdateKernels* kernelsFor(UpdateKernelIsa isa) {
#ifdef EKF_LOCAL_MAP_AVX2_KERNELS
  if (isa == UpdateKernelIsa::kAvx2Fma) return &kAvx2Kernels;
#endif
  (void)isa;
  return &kPortableKernels;
}

std::atomic<const UpdateKernels*>& activeKernels() {
  static std::atomic<const UpdateKernels*> kernels{
      kernelsFor(cpuHasAvx2Fma() ? UpdateKernelIsa::kAvx2Fma : UpdateKernelIsa::kPortable)};
  return kernels;
}

}  // namespace

const UpdateKernels& activeUpdateKernels() { return *activeKernels().load(std::memory_order_relaxed); }

UpdateKernelIsa updateKernelIsa() {
  return activeKernels().load(std::memory_order_relaxed) == &kPortableKernels ? UpdateKernelIsa::kPortable
                                                                              : UpdateKernelIsa::kAvx2Fma;
}

bool setUpdateKernelIsa(UpdateKernelIsa isa) {
  if (isa == UpdateKernelIsa::kAvx2Fma && !cpuHasAvx2Fma()) return false;
  activeKernels().store(kernelsFor(isa), std::memory_order_relaxed);
  return true;
}

}  // namespace ekf_local_map
