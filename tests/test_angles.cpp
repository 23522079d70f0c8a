// SPDX-License-Identifier: MIT
// The angle energies' first-quadrant atan2 against the exact angle (long double atan2l) on
// seeded random arguments: every range of its reduction, ratios across the whole exponent
// range, and the values std::atan2 gives exactly.
#include "energy/angles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace depath {
namespace {

// |got - atan2(y, x)| in units in the last place of the exactly rounded result.
double ulp_error(double got, double y, double x) {
  const long double exact = std::atan2(static_cast<long double>(y), static_cast<long double>(x));
  const double rounded = static_cast<double>(exact);
  const double ulp = rounded > 0.0 ? std::nextafter(rounded, 2.0 * rounded + 1.0) - rounded
                                   : std::numeric_limits<double>::denorm_min();
  return static_cast<double>(std::abs(static_cast<long double>(got) - exact) / ulp);
}

TEST(FirstQuadrantAtan2, WithinTwoUlpOfTheExactAngleOnRandomArguments) {
  std::mt19937_64 rng(20261208);
  std::uniform_real_distribution<double> unit(0.0, 1.0), exponent(-60.0, 60.0), jitter(-1e-3, 1e-3);
  // The reduction's switch points: y / x = 0.66 and tan(3 pi / 8), and the diagonal.
  const double ratios[3] = {0.66, 2.41421356237309504880, 1.0};
  double worst[4] = {0.0, 0.0, 0.0, 0.0};
  for (int i = 0; i < 400000; ++i) {
    const int family = i % 4;
    double y = 0.0, x = 0.0;
    if (family == 0) {  // uniform in the unit square
      y = unit(rng), x = unit(rng);
    } else if (family == 1) {  // ratios from 2^-120 to 2^120
      y = std::ldexp(unit(rng), static_cast<int>(exponent(rng)));
      x = std::ldexp(unit(rng), static_cast<int>(exponent(rng)));
    } else {  // near a switch point
      x = std::ldexp(unit(rng) + 0.5, static_cast<int>(exponent(rng)) / 4);
      y = x * ratios[i % 3] * (1.0 + (family == 2 ? jitter(rng) : 1e-3 * jitter(rng)));
    }
    const double got = first_quadrant_atan2(y, x);
    ASSERT_GE(got, 0.0) << y << " " << x;
    ASSERT_LE(got, std::numbers::pi / 2) << y << " " << x;
    const double error = ulp_error(got, y, x);
    worst[family] = std::max(worst[family], error);
    ASSERT_LE(error, 2.0) << "atan2(" << y << ", " << x << ") = " << got;
  }
  // Cephes' approximation is near the rounding limit, not just inside the bound.
  for (double w : worst) EXPECT_GT(w, 0.5);
}

TEST(FirstQuadrantAtan2, AxesDiagonalAndZeroAsStdAtan2) {
  const double tiny = std::numeric_limits<double>::denorm_min(), huge = std::numeric_limits<double>::max();
  EXPECT_EQ(first_quadrant_atan2(0.0, 0.0), 0.0);
  for (double v : {tiny, 1e-300, 1.0, 3.5, 1e300, huge}) {
    EXPECT_EQ(first_quadrant_atan2(0.0, v), 0.0) << v;
    EXPECT_EQ(first_quadrant_atan2(v, 0.0), std::atan2(1.0, 0.0)) << v;
    EXPECT_EQ(first_quadrant_atan2(v, v), std::atan2(1.0, 1.0)) << v;
  }
  EXPECT_EQ(first_quadrant_atan2(1e-300, 1.0), 1e-300);  // atan(r) = r for tiny r
}

TEST(AcuteAngle, IsTheAngleBetweenLinesWhateverTheirLengthAndOrientation) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi), scale(1e-3, 1e3);
  for (int i = 0; i < 10000; ++i) {
    const double a = angle(rng), b = angle(rng), la = scale(rng), lb = scale(rng);
    double expected = std::abs(std::remainder(a - b, std::numbers::pi));  // in [0, pi/2]
    const double got = acute_angle(la * std::cos(a), la * std::sin(a), lb * std::cos(b), lb * std::sin(b));
    EXPECT_NEAR(got, expected, 1e-12) << a << " " << b;
    // Reversing either line changes nothing.
    EXPECT_EQ(got, acute_angle(-la * std::cos(a), -la * std::sin(a), lb * std::cos(b), lb * std::sin(b)));
  }
}

}  // namespace
}  // namespace depath
