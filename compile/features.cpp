// compile/features.cpp — what a scene uses (features.hpp), and its name for humans.
#include <octray/features.hpp>

namespace octray {

Features features_of(const Scene& scene) {
    Features f;
    for (const Object& o : scene.objects) f.bits |= 1u << unsigned(primitive_type(o.shape));
    if (scene.mesh_triangle_count() > 0) f.bits |= kTriangle;  // mesh triangles are triangles
    if (scene.ambient) f.bits |= kAmbient;
    if (scene.ambient && scene.ambient_occlusion) f.bits |= kOcclusion;
    for (const DirectionalLight& l : scene.directional_lights) {
        f.bits |= kDirectional;
        if (l.shadows) f.bits |= kShadows;
    }
    for (const PointLight& l : scene.point_lights) {
        f.bits |= l.attenuation == Attenuation::inverse_square ? kPointAttenuated : kPoint;
        if (l.shadows) f.bits |= kShadows;
    }
    f.tonemap = scene.render.tonemap;
    f.gamma = scene.render.gamma != 1.0;
    return f;
}

std::string feature_string(unsigned bits) {
    // Bits 0-5 are the primitive types (scene.hpp names them), then the lights' features.
    static constexpr const char* light_names[] = {"ambient", "directional", "point", "point_attenuated", "shadows",
                                                  "occlusion"};
    std::string prims, lights;
    for (unsigned i = 0; i < 12; ++i) {
        if ((bits & (1u << i)) == 0) continue;
        std::string& s = i < kPrimitiveTypeCount ? prims : lights;
        if (!s.empty()) s += '+';
        s += i < kPrimitiveTypeCount ? primitive_type_name(PrimitiveType(i)) : light_names[i - kPrimitiveTypeCount];
    }
    return (prims.empty() ? "no primitives" : prims) + " | " + (lights.empty() ? "no lights" : lights);
}

}  // namespace octray
