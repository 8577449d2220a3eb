// dispatch/isa_instantiate.hpp — instantiates the kernels of kernels/packet_kernels.hpp
// for one unit's lane types and fills a Kernel table. Included by the per-ISA
// units after kernels/packet_kernels.hpp, inside the same OCTRAY_ISA namespace scheme.
#pragma once

#include "dispatch/isa_kernels.hpp"

#include <utility>

namespace octray::kernels::OCTRAY_ISA {

// Calls fn(std::integral_constant<Precision, p>{}): a run-time mode to a compile-time one.
template <class Fn>
auto with_precision(Precision p, Fn&& fn) {
    using E = Precision;
    switch (p) {
    case E::fast: return fn(std::integral_constant<E, E::fast>{});
    case E::approx: return fn(std::integral_constant<E, E::approx>{});
    case E::fast14: return fn(std::integral_constant<E, E::fast14>{});
    case E::approx14: return fn(std::integral_constant<E, E::approx14>{});
    case E::f64: return fn(std::integral_constant<E, E::f64>{});
    case E::exact: break;
    }
    return fn(std::integral_constant<E, E::exact>{});
}

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

// Spheres and planes: the primitive set of the occlusion variant and of occluded's own.
inline constexpr unsigned kAnalytic = kSphere | kPlane;

template <class T, Precision P, bool Specialize>
Kernel make_kernel_at(Path path, const char* isa, unsigned primitive_bits, unsigned light_bits) {
    Kernel k;
    k.path = path;
    k.precision = P;
    k.isa = isa;
    k.tonemap = &tonemap_packet<T, P>;
    k.tonemap_group = &tonemap_group<T, P>;
    k.camera = &camera_packet<T, P>;
    k.occluded = &occluded_packet<T, P, kAllPrimitives>;
    k.intersect_fields = &intersect_fields_packet<T, P, kAllFeatures>;
    if constexpr (Specialize) {
        const unsigned pi = primitive_bits & kAllPrimitives, li = (light_bits >> kLightShift) & (kLightVariants - 1);
        k.intersect = intersect_variants<T, P>(std::make_index_sequence<kPrimitiveVariants>{})[pi];
        k.shade = shade_variants<T, P>(std::make_index_sequence<kLightVariants>{})[li];
        k.primitive_bits = pi;
        k.light_bits = li << kLightShift;
        // Spheres and planes alone (aobench's kind of scene): occluded walks
        // those two types only, as the occlusion kernel's rays do.
        if ((pi & ~kAnalytic) == 0) k.occluded = &occluded_packet<T, P, kAnalytic>;
        if ((light_bits & kOcclusion) != 0) {
            // Occlusion doubles no table: an ambient-only scene of spheres and
            // planes (aobench; Suffern's occluder figures) has its own variant,
            // whose sample rays walk those two types only; every other scene
            // with occlusion runs the general shade.
            const bool own = (light_bits & ~kAllPrimitives) == (kAmbient | kOcclusion) && (pi & ~kAnalytic) == 0;
            k.shade = own ? &shade_packet<T, P, kAmbient | kOcclusion | kAnalytic> : &shade_packet<T, P, kAllFeatures>;
            k.light_bits = own ? kAmbient | kOcclusion : kAllFeatures & ~kAllPrimitives;
        }
    } else {
        (void)primitive_bits, (void)light_bits;
        k.intersect = &intersect_packet<T, P, kAllFeatures>;
        k.shade = &shade_packet<T, P, kAllFeatures>;
        k.primitive_bits = kAllPrimitives;
        k.light_bits = kAllFeatures & ~kAllPrimitives;
    }
    return k;
}

// What one unit compiles: float lanes F for the float modes in `Modes` (a
// mode_bit set), double lanes D for Precision::f64 (D unused without it).
// Exact precision is specialized on the scene's features when `Specialize`;
// every other mode is compiled once, general (all features), to keep the
// number of instantiations in check. A mode outside `Modes` gives an empty
// Kernel (intersect == nullptr): dispatch never asks for one.
template <class F, class D, unsigned Modes, bool Specialize>
Kernel make_kernel(Path path, const char* isa, Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return with_precision(precision, [&](auto mode) -> Kernel {
        constexpr Precision P = decltype(mode)::value;
        if constexpr ((Modes & mode_bit(P)) == 0) {
            return {};
        } else if constexpr (P == Precision::f64) {
            return make_kernel_at<D, P, false>(path, isa, 0, 0);
        } else {
            if constexpr (Specialize && P == Precision::exact)
                if (primitive_bits != kAllFeatures) return make_kernel_at<F, P, true>(path, isa, primitive_bits, light_bits);
            return make_kernel_at<F, P, false>(path, isa, 0, 0);
        }
    });
}

}  // namespace octray::kernels::OCTRAY_ISA
