// The BVH walks with 8-float node batches, on 8-float and 4-double packets and
// single float rays: bvh_traversal_checks.hpp at AVX2. Part of
// octray_tests_avx2, a binary built wholly with -mavx2 -mfma
// (tests/CMakeLists.txt), so nothing compiled for AVX2 shares a binary with
// the default-target tests.
#define OCTRAY_ISA bvh_test_avx2
#include "bvh_traversal_checks.hpp"

namespace octray::test {
namespace {

TEST_CASE("bvh walks at AVX2: 8-float node batches, 8-float and 4-double packets") {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
        MESSAGE("this CPU has no AVX2: skipped");
        return;
    }
    check_walks<float>(101u, 120);
    check_walks<xsimd::batch<float, xsimd::fma3<xsimd::avx2>>>(102u, 40);
    check_walks<xsimd::batch<double, xsimd::fma3<xsimd::avx2>>>(103u, 40);
    check_child_order(104u);
}

}  // namespace
}  // namespace octray::test
