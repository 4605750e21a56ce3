// sin and cos of a batch of angles, inline, for the per-link cost of the kinematics.
//
// libm's sincos is a call that costs 16-34 ns on the reference machine and forces the running
// frame out of registers around it; with eight revolute joints it was two thirds of forward
// kinematics (docs/performance.md). Joint angles are small (|x| < 1e5 rad here; beyond that
// and for NaN this falls back to libm), so a short Cody-Waite reduction to [-pi/4, pi/4]
// followed by the fdlibm kernel polynomials (__kernel_sin, __kernel_cos: minimax, error below
// 2^-58 on that interval) gives results within a couple of ulp of libm. The loop has no calls
// and no branches; on x86-64 it runs two angles at a time in SSE2. test_sincos compares it with
// libm.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace redpost::detail {

// The coefficients: pi/2 in three parts of 33, 33 and 53 bits (fdlibm), so that k * part1 and
// k * part2 are exact for |k| < 2^20 and r keeps full precision; the kernel polynomials.
struct SinCosConstants {
  static constexpr double two_over_pi = 6.36619772367581382433e-01;
  static constexpr double pio2_1 = 1.57079632673412561417e+00;
  static constexpr double pio2_2 = 6.07710050630396597660e-11;
  static constexpr double pio2_3 = 2.02226624879595063154e-21;
  // Adding 1.5 * 2^52 rounds to the nearest integer, which then sits in the low mantissa bits
  // (as k mod 2^51, also for negative k).
  static constexpr double round_shift = 6755399441055744.0;
  static constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                          S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                          S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  static constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                          C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                          C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
};

// One angle; the reference for the vector version below.
inline void sincos_one(double x, double& s_out, double& c_out) {
  using K = SinCosConstants;
  const double shifted = x * K::two_over_pi + K::round_shift;
  const double k = shifted - K::round_shift;
  const double r = ((x - k * K::pio2_1) - k * K::pio2_2) - k * K::pio2_3;
  const double z = r * r;
  const double sin_r =
      r + r * z * (K::S1 + z * (K::S2 + z * (K::S3 + z * (K::S4 + z * (K::S5 + z * K::S6)))));
  const double cos_r =
      1.0 - 0.5 * z +
      z * z * (K::C1 + z * (K::C2 + z * (K::C3 + z * (K::C4 + z * (K::C5 + z * K::C6)))));
  // Quadrant k mod 4: (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
  std::uint64_t q;
  std::memcpy(&q, &shifted, sizeof q);
  const double s = (q & 1) != 0 ? cos_r : sin_r;
  const double c = (q & 1) != 0 ? sin_r : cos_r;
  s_out = (q & 2) != 0 ? -s : s;
  c_out = ((q + 1) & 2) != 0 ? -c : c;
}

inline void sincos_batch(const double* x, double* s_out, double* c_out, int n) {
  int i = 0;
#if defined(__SSE2__)
  // Two angles per SSE2 register (the x86-64 baseline): the same operations as sincos_one,
  // with the quadrant selection done by bit masks instead of branches.
  using K = SinCosConstants;
  const __m128d shift = _mm_set1_pd(K::round_shift);
  for (; i + 2 <= n; i += 2) {
    const __m128d xv = _mm_loadu_pd(x + i);
    const __m128d shifted = _mm_add_pd(_mm_mul_pd(xv, _mm_set1_pd(K::two_over_pi)), shift);
    const __m128d k = _mm_sub_pd(shifted, shift);
    __m128d r = _mm_sub_pd(xv, _mm_mul_pd(k, _mm_set1_pd(K::pio2_1)));
    r = _mm_sub_pd(r, _mm_mul_pd(k, _mm_set1_pd(K::pio2_2)));
    r = _mm_sub_pd(r, _mm_mul_pd(k, _mm_set1_pd(K::pio2_3)));
    const __m128d z = _mm_mul_pd(r, r);
    auto horner = [&z](double c0, double c1, double c2, double c3, double c4, double c5) {
      __m128d p = _mm_set1_pd(c5);
      p = _mm_add_pd(_mm_mul_pd(p, z), _mm_set1_pd(c4));
      p = _mm_add_pd(_mm_mul_pd(p, z), _mm_set1_pd(c3));
      p = _mm_add_pd(_mm_mul_pd(p, z), _mm_set1_pd(c2));
      p = _mm_add_pd(_mm_mul_pd(p, z), _mm_set1_pd(c1));
      return _mm_add_pd(_mm_mul_pd(p, z), _mm_set1_pd(c0));
    };
    const __m128d ps = horner(K::S1, K::S2, K::S3, K::S4, K::S5, K::S6);
    const __m128d pc = horner(K::C1, K::C2, K::C3, K::C4, K::C5, K::C6);
    const __m128d sin_r = _mm_add_pd(r, _mm_mul_pd(_mm_mul_pd(r, z), ps));
    const __m128d cos_r = _mm_add_pd(_mm_sub_pd(_mm_set1_pd(1.0), _mm_mul_pd(_mm_set1_pd(0.5), z)),
                                     _mm_mul_pd(_mm_mul_pd(z, z), pc));
    const __m128i q = _mm_castpd_si128(shifted);
    const __m128i one = _mm_set1_epi64x(1), two = _mm_set1_epi64x(2);
    // swap = all ones where q is odd; sign bits where q & 2 (sin) and (q + 1) & 2 (cos).
    const __m128d swap =
        _mm_castsi128_pd(_mm_sub_epi64(_mm_setzero_si128(), _mm_and_si128(q, one)));
    const __m128d sign_s = _mm_castsi128_pd(_mm_slli_epi64(_mm_and_si128(q, two), 62));
    const __m128d sign_c =
        _mm_castsi128_pd(_mm_slli_epi64(_mm_and_si128(_mm_add_epi64(q, one), two), 62));
    const __m128d s = _mm_or_pd(_mm_and_pd(swap, cos_r), _mm_andnot_pd(swap, sin_r));
    const __m128d c = _mm_or_pd(_mm_and_pd(swap, sin_r), _mm_andnot_pd(swap, cos_r));
    _mm_storeu_pd(s_out + i, _mm_xor_pd(s, sign_s));
    _mm_storeu_pd(c_out + i, _mm_xor_pd(c, sign_c));
  }
#endif
  for (; i < n; ++i)
    sincos_one(x[i], s_out[i], c_out[i]);
  for (i = 0; i < n; ++i) {
    if (!(std::fabs(x[i]) < 1e5)) {  // far outside any joint range, or NaN: libm decides
      s_out[i] = std::sin(x[i]);
      c_out[i] = std::cos(x[i]);
    }
  }
}

}  // namespace redpost::detail
