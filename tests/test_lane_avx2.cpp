// kernels/lanes/lane.hpp's intrinsic paths: lane_checks.hpp at AVX2. Part of
// octray_tests_avx2, a binary built wholly with -mavx2 -mfma.
#include "lane_checks.hpp"

namespace octray::test {
namespace {

TEST_CASE("the same lane checks at AVX2 (kernels/lanes/lane.hpp's intrinsic paths)") {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
        MESSAGE("this CPU has no AVX2: skipped");
        return;
    }
    using B = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
    check_min_max_nan_rule<B>();
    check_uniform_on<B>();
    check_horizontal<B>();
    check_keep<B>();
}

}  // namespace
}  // namespace octray::test
