// Runs a test body once for every Highway target compiled in that this CPU supports, each made the
// one HWY_DYNAMIC_DISPATCH chooses while the body runs, so that a SIMD kernel is checked on every
// instruction set it may meet (here AVX-512, AVX2, SSE4, SSSE3 and the scalar fallback).
#pragma once

#include <catch2/catch.hpp>
#include <hwy/targets.h>

#include <cstdint>

namespace highway_tests {

// f(target) for each target; at least one must run.
template <class F>
void for_each_target(F&& f) {
    const int64_t supported = hwy::SupportedTargets();
    int tried = 0;
    for (int64_t target = 1; target != 0 && target <= supported; target <<= 1) {
        if (!(supported & target) || !(HWY_TARGETS & target)) continue;
        hwy::SetSupportedTargetsForTest(target);
        hwy::GetChosenTarget().Update(hwy::SupportedTargets());
        INFO("Highway target " << hwy::TargetName(target));
        f(target);
        ++tried;
    }
    hwy::SetSupportedTargetsForTest(0);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    CHECK(tried >= 1);
}

}  // namespace highway_tests
