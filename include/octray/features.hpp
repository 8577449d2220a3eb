// octray/features.hpp — what a scene uses, so its kernel can leave out the rest.
#pragma once

#include <octray/scene.hpp>

#include <string>

namespace octray {

// One bit per feature a kernel can be specialized on.
enum FeatureBit : unsigned {
    kSphere = 1u << 0,
    kPlane = 1u << 1,
    kDisk = 1u << 2,
    kRectangle = 1u << 3,
    kBox = 1u << 4,
    kTriangle = 1u << 5,
    kAmbient = 1u << 6,
    kDirectional = 1u << 7,
    kPoint = 1u << 8,             // point lights without attenuation
    kPointAttenuated = 1u << 9,   // point lights with inverse-square attenuation
    kShadows = 1u << 10,          // at least one light casts shadows
    kOcclusion = 1u << 11,        // the ambient light has occlusion (needs kAmbient)
};
inline constexpr unsigned kAllPrimitives = kSphere | kPlane | kDisk | kRectangle | kBox | kTriangle;
inline constexpr unsigned kAllFeatures = (1u << 12) - 1;

struct Features {
    unsigned bits = 0;
    ToneMap tonemap = ToneMap::max_to_one;
    bool gamma = false;  // gamma != 1

    bool has(unsigned b) const { return (bits & b) == b; }
};

Features features_of(const Scene& scene);

// "sphere+plane | ambient+directional | shadows" — for humans.
std::string feature_string(unsigned bits);

}  // namespace octray
