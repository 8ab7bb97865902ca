#pragma once
// The one table of tolerances for device results against double-precision host twins (docs/design.md §8),
// and canaries that catch kernels writing past the end of their output.
#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

namespace clr::test {

struct Tolerance {
  double rel;
  double abs;
};

// float32 kernels vs a double twin: 0.5 % relative or 1e-3 absolute, whichever is looser. Reductions in a
// different order and fused multiply-adds differ from the twin by a few ulp per term; 0.5 % covers sums of
// thousands of terms with room to spare while still catching a wrong index or a missing term.
inline constexpr Tolerance kFloatKernel{5e-3, 1e-3};

inline ::testing::AssertionResult near(double got, double want, Tolerance tol = kFloatKernel) {
  const double err = std::abs(got - want);
  if (std::isfinite(got) && err <= std::max(tol.abs, tol.rel * std::abs(want))) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got " << got << ", want " << want << " (|err| " << err << ")";
}

// `extra_abs`, where given, adds an absolute allowance of each element's own to `tol` (a reduced-precision kernel's
// error bound, which depends on the element's terms).
template <typename Got, typename Want>
::testing::AssertionResult all_near(std::span<const Got> got, std::span<const Want> want, Tolerance tol = kFloatKernel,
                                    std::span<const double> extra_abs = {}) {
  if (got.size() != want.size()) return ::testing::AssertionFailure() << "size " << got.size() << " vs " << want.size();
  for (std::size_t i = 0; i < got.size(); ++i) {
    const Tolerance t{tol.rel, tol.abs + (extra_abs.empty() ? 0.0 : extra_abs[i])};
    if (auto r = near(double(got[i]), double(want[i]), t); !r) return r << " at index " << i;
  }
  return ::testing::AssertionSuccess();
}

// Canary values written after an output buffer's payload and checked after the kernel ran.
inline constexpr float kCanary = -1234.5f;
inline constexpr std::size_t kCanaryCount = 64;

}  // namespace clr::test

namespace clr::test {

// Host data for an output buffer: n payload elements (set to `fill`) followed by kCanaryCount canaries.
inline std::vector<float> with_canaries(std::size_t n, float fill = 0.0f) {
  std::vector<float> v(n + kCanaryCount, kCanary);
  std::fill_n(v.begin(), n, fill);
  return v;
}

inline ::testing::AssertionResult canaries_intact(std::span<const float> v, std::size_t n) {
  for (std::size_t i = n; i < v.size(); ++i)
    if (v[i] != kCanary) return ::testing::AssertionFailure() << "canary overwritten at payload+" << (i - n);
  return ::testing::AssertionSuccess();
}

}  // namespace clr::test
