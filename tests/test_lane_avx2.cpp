// Built with -mavx2 -mfma (tests/CMakeLists.txt): lane.hpp's AVX2 paths.
#include "lane_checks.hpp"

namespace octray::test {

bool avx2_lane_checks() {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return false;
    using B = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
    check_min_max_nan_rule<B>();
    check_uniform_on<B>();
    check_horizontal<B>();
    check_keep<B>();
    return true;
}

}  // namespace octray::test
