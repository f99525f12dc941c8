// The pressure kernel (fluid/pressure_kernel.h) on four faces at a time with AVX2: one face
// per lane of a 256-bit register. No FMA (the target below has none, and the file is built
// with -ffp-contract=off): every lane rounds as the scalar path does. This unit is compiled
// for AVX2 by the pragma and holds nothing but the kernel; PressureBatch calls it only where
// the CPU has AVX2. Private to flapsim_core.
#include <immintrin.h>

#pragma GCC push_options
#pragma GCC target("avx2")

#include "fluid/pressure_kernel.h"

namespace flapsim {

namespace {

struct Avx2Lane {
  static constexpr int kWidth = 4;
  __m256d v;
  static Avx2Lane splat(double x) { return {_mm256_set1_pd(x)}; }
  static Avx2Lane load(const double* p) { return {_mm256_loadu_pd(p)}; }
  static void store(double* p, Avx2Lane x) { _mm256_storeu_pd(p, x.v); }
  // MAX(a, b) is a > b ? a : b: (0 > x ? 0 : x) and (x > 0 ? x : 0), as ScalarLane.
  static Avx2Lane max0(Avx2Lane x) { return {_mm256_max_pd(_mm256_setzero_pd(), x.v)}; }
  static Avx2Lane maxPositive(Avx2Lane x) { return {_mm256_max_pd(x.v, _mm256_setzero_pd())}; }
  static Avx2Lane sqrt(Avx2Lane x) { return {_mm256_sqrt_pd(x.v)}; }
  // `b` where the sign bit of `swap` is set (-1), else `a`.
  static Avx2Lane select(Avx2Lane swap, Avx2Lane a, Avx2Lane b) {
    return {_mm256_blendv_pd(a.v, b.v, swap.v)};
  }
  // All bits set where x is not <= 0 (NaN too), else none; onlyIf keeps x there, else +0.
  static Avx2Lane notAtMostZero(Avx2Lane x) {
    return {_mm256_cmp_pd(x.v, _mm256_setzero_pd(), _CMP_NLE_UQ)};
  }
  static Avx2Lane onlyIf(Avx2Lane mask, Avx2Lane x) { return {_mm256_and_pd(mask.v, x.v)}; }
  static Avx2Lane gather(const double* column, const int* body) {
    return {_mm256_i32gather_pd(column, _mm_loadu_si128(reinterpret_cast<const __m128i*>(body)),
                                sizeof(double))};
  }
};
inline Avx2Lane operator+(Avx2Lane a, Avx2Lane b) { return {_mm256_add_pd(a.v, b.v)}; }
inline Avx2Lane operator-(Avx2Lane a, Avx2Lane b) { return {_mm256_sub_pd(a.v, b.v)}; }
inline Avx2Lane operator*(Avx2Lane a, Avx2Lane b) { return {_mm256_mul_pd(a.v, b.v)}; }

}  // namespace

// Declared in fluid/pressure_batch.cpp, the only caller.
void pressureTableAvx2(double* table, int stride, int squares, const Flows& flows, bool wind) {
  pressureTable<Avx2Lane, GridShape::k4x4>(table, stride, 0, squares, flows, wind);
  pressureTable<Avx2Lane, GridShape::k1x4>(table, stride, squares, stride, flows, wind);
}

}  // namespace flapsim

#pragma GCC pop_options
