// The library's arithmetic is the same in every build: the compiler fuses no a*b + c into one
// multiply-add on its own (-ffp-contract=off), so a native build (-march=native, FMA) rounds like
// the portable one and their outputs are the same bytes. Composing maps is the inner step of the
// recursive renderers (PRR, volume PRR); here its products are chosen so that fusing changes the sum.
#include <gtest/gtest.h>

#include <cmath>

#include "ifsforge/model/affine_map.h"

namespace ifsforge {
namespace {

// (1 + 2^-27)(1 - 2^-27) = 1 - 2^-54: rounded alone it is 1 (a tie, to even), so added to -1 it
// gives 0; a fused multiply-add keeps the product exact and gives -2^-54.
const double kUp = 1.0 + std::ldexp(1.0, -27);
const double kDown = 1.0 - std::ldexp(1.0, -27);

// Outer and inner maps of dimension n whose composition's a(0,0) and b(0) each end in the sum
// -1 + kUp * kDown; the other coefficients are those of the identity.
void tie_maps(int n, AffineMap& outer, AffineMap& inner) {
  outer = AffineMap(n);
  inner = AffineMap(n);
  for (int i = 0; i < n; ++i) outer.a(i, i) = inner.a(i, i) = 1.0;
  outer.a(0, 0) = -1.0;
  outer.a(0, 1) = kUp;
  outer.b(0) = -1.0;
  inner.a(1, 0) = kDown;
  inner.b(1) = kDown;
}

TEST(UnfusedArithmetic, TheProductIsRoundedBeforeTheSum) {
  ASSERT_EQ(kUp * kDown, 1.0);
  ASSERT_EQ(std::fma(kUp, kDown, -1.0), -std::ldexp(1.0, -54));  // what a fused sum would give
}

TEST(UnfusedArithmetic, ComposingMapsRoundsEveryProductInEveryDimension) {
  for (int n = 2; n <= 4; ++n) {  // 2 and 3 take the unrolled compositions, 4 the general one
    AffineMap outer(n), inner(n);
    tie_maps(n, outer, inner);
    const AffineMap out = outer.compose(inner);
    EXPECT_EQ(out.a(0, 0), 0.0) << n << "D";  // -1 * 1 + kUp * kDown
    EXPECT_EQ(out.b(0), 0.0) << n << "D";     // -1 + kUp * kDown
    EXPECT_EQ(out.a(0, 1), kUp) << n << "D";
    EXPECT_EQ(out.b(1), kDown) << n << "D";
  }
}

}  // namespace
}  // namespace ifsforge
