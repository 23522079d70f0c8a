// SPDX-License-Identifier: MIT
#include "decode/log_densities.hpp"

#include <bit>
#include <cfloat>
#include <cstddef>
#include <cstdint>

namespace depath {
namespace {

// exp(x) = 2^k exp(r), k = round(x / ln 2), |r| <= ln 2 / 2, with ln 2 split in two so
// that r is exact; exp(r) by its Taylor polynomial of degree 13 (truncation < 1e-17).
constexpr double kLog2e = 1.4426950408889634;
constexpr double kLn2Hi = 6.93147180369123816490e-01;
constexpr double kLn2Lo = 1.90821492927058770002e-10;
// Adding 1.5 * 2^52 rounds to an integer and leaves it in the low mantissa bits.
constexpr double kShift = 0x1.8p52;
// Below exp(-745.2) a double underflows to 0, above exp(709.79) it overflows: clamp the
// argument there and the result to [DBL_MIN, DBL_MAX] afterwards.
constexpr double kLowest = -745.2;
constexpr double kHighest = 709.79;

// 2^k for an integer-valued k in [-1022, 1023], from its bits.
inline double power_of_two(double k) { return std::bit_cast<double>((std::bit_cast<uint64_t>(k + kShift) + 1023) << 52); }

}  // namespace

// Same source compiled three times; the same operations in the same order, so every clone
// gives the same bits (no FMA contraction: -ffp-contract=off is set for this file). The
// baseline x86-64 clone is not vectorised (no packed 64-bit shifts worth it): about as
// slow as std::exp, the AVX2 / AVX-512 ones 8x faster. ThreadSanitizer builds get the
// plain function: clones are chosen by an ifunc resolver that runs before TSan's runtime
// is up and crashes the process.
#if defined(__x86_64__) && !defined(__SANITIZE_THREAD__)
__attribute__((target_clones("avx512f", "avx2", "default")))
#endif
void densities_from_logs(std::span<const double> log_density, std::span<double> density) {
  const double* __restrict in = log_density.data();
  double* __restrict out = density.data();
  const size_t n = log_density.size();
  for (size_t i = 0; i < n; ++i) {
    double x = in[i];
    x = x > kLowest ? x : kLowest;  // NaN -> kLowest
    x = x < kHighest ? x : kHighest;
    const double shifted = x * kLog2e + kShift;
    const double k = shifted - kShift;
    const double r = (x - k * kLn2Hi) - k * kLn2Lo;
    double p = 1.0 / 6227020800.0;
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r + 1.0;
    p = p * r + 1.0;
    // 2^k as 2^k1 * 2^k2 so that each factor stays a normal number for k in [-1075, 1024].
    const double k1 = (0.5 * k + kShift) - kShift;
    double e = p * power_of_two(k1) * power_of_two(k - k1);
    e = e > DBL_MIN ? e : DBL_MIN;
    out[i] = e < DBL_MAX ? e : DBL_MAX;
  }
}

}  // namespace depath
