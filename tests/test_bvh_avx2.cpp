// Built with -mavx2 -mfma (tests/CMakeLists.txt): the BVH walks with 8-float
// node batches, on 8-float and 4-double packets and single float rays.
#define OCTRAY_ISA bvh_test_avx2
#include "bvh_traversal_checks.hpp"

namespace octray::test {

bool avx2_bvh_checks() {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return false;
    check_walks<float>(101u, 120);
    check_walks<xsimd::batch<float, xsimd::fma3<xsimd::avx2>>>(102u, 40);
    check_walks<xsimd::batch<double, xsimd::fma3<xsimd::avx2>>>(103u, 40);
    check_child_order(104u);
    return true;
}

}  // namespace octray::test
