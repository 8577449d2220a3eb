// kernels/isa_instantiate.hpp — instantiates the kernels of packet_kernels.hpp
// for one lane type and fills a Kernel table. Included by the per-ISA units
// after packet_kernels.hpp, inside the same OCTRAY_ISA namespace scheme.
#pragma once

#include "isa_kernels.hpp"

#include <utility>

namespace octray::kernels::OCTRAY_ISA {

template <class T, Precision P, std::size_t... I>
const IntersectFn* intersect_variants(std::index_sequence<I...>) {
    static constexpr IntersectFn table[] = {&intersect_packet<T, P, unsigned(I)>...};
    return table;
}
template <class T, Precision P, std::size_t... I>
const ShadeFn* shade_variants(std::index_sequence<I...>) {
    static constexpr ShadeFn table[] = {&shade_packet<T, P, unsigned(I) << kLightShift>...};
    return table;
}

template <class T, Precision P, bool Specialize>
Kernel make_kernel_at(Path path, const char* isa, unsigned primitive_bits, unsigned light_bits) {
    Kernel k;
    k.path = path;
    k.precision = P;
    k.isa = isa;
    k.tonemap = &tonemap_packet<T, P>;
    k.camera = &camera_packet<T, P>;
    k.occluded = &occluded_packet<T, P, kAllPrimitives>;
    if constexpr (Specialize) {
        const unsigned pi = primitive_bits & kAllPrimitives, li = (light_bits >> kLightShift) & (kLightVariants - 1);
        k.intersect = intersect_variants<T, P>(std::make_index_sequence<kPrimitiveVariants>{})[pi];
        k.shade = shade_variants<T, P>(std::make_index_sequence<kLightVariants>{})[li];
        k.primitive_bits = pi;
        k.light_bits = li << kLightShift;
    } else {
        (void)primitive_bits, (void)light_bits;
        k.intersect = &intersect_packet<T, P, kAllFeatures>;
        k.shade = &shade_packet<T, P, kAllFeatures>;
        k.primitive_bits = kAllPrimitives;
        k.light_bits = kAllFeatures & ~kAllPrimitives;
    }
    return k;
}

// Exact precision: the variant for exactly (primitive_bits, light_bits) when
// `Specialize` and the bits are not kAllFeatures; otherwise the general kernel.
template <class T, bool Specialize>
Kernel make_kernel(Path path, const char* isa, Precision precision, unsigned primitive_bits, unsigned light_bits) {
    switch (precision) {
    case Precision::exact:
        if (Specialize && primitive_bits != kAllFeatures)
            return make_kernel_at<T, Precision::exact, Specialize>(path, isa, primitive_bits, light_bits);
        return make_kernel_at<T, Precision::exact, false>(path, isa, 0, 0);
    case Precision::fast: return make_kernel_at<T, Precision::fast, false>(path, isa, 0, 0);
    case Precision::approx: return make_kernel_at<T, Precision::approx, false>(path, isa, 0, 0);
    }
    return {};
}

}  // namespace octray::kernels::OCTRAY_ISA
