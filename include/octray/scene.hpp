// octray/scene.hpp — scene authoring types (array-of-structures, double).
//
// This is what the JSON loader produces and what an engine may build by hand.
// Invariants (validate() holds the rules; the loader and compile() apply it):
// radii and extents are positive, material indices are in range, every number
// is finite (see validate()). Field meanings follow docs/scene-format.md and
// docs/shading-model.md.
//
// Directions (DirectionalLight::direction, Plane::normal, Disk::normal,
// Camera::up) need not be unit length: any finite, non-zero vector is valid,
// and every path (reference, scalar, simd) uses it as unit_direction(v), the
// one normalization below. So a hand-built scene with direction {1, 2, 1}
// renders the same on every path; the JSON loader stores them normalized.
#pragma once

#include <octray/constants.hpp>
#include <octray/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace octray {

enum class CameraType { pinhole, orthographic };
// Each enum's names (the JSON and CLI spelling), in enumerator order, defined
// once beside it; the loader, the CLI and the tools read them from here.
inline constexpr const char* kCameraTypeNames[] = {"pinhole", "orthographic"};
inline constexpr const char* camera_type_name(CameraType t) { return kCameraTypeNames[static_cast<int>(t)]; }

struct Camera {
    CameraType type = CameraType::pinhole;
    Vec3d eye{0, 0, 5};
    Vec3d look_at{0, 0, 0};
    Vec3d up{0, 1, 0};      // any length (see above), not parallel to eye - look_at
    double fov_y = 45.0;    // degrees, pinhole only, in (0, 180)
    double height_world = 2.0;  // orthographic only, > 0
    int width = 320;
    int height = 240;
};

// Matte material: Lambertian BRDF (docs/shading-model.md).
struct Material {
    std::string name;
    double ka = 0.25;  // ambient reflection coefficient, >= 0
    double kd = 0.65;  // diffuse reflection coefficient, >= 0
    Vec3d cd{1, 1, 1}; // diffuse colour, components >= 0
};

// Ambient occlusion (docs/shading-model.md; Suffern ch. 17): the ambient term times
// max(min_amount, the fraction of `samples` cosine-weighted rays over the
// hemisphere about the facing normal that nothing blocks before `distance`).
struct AmbientOcclusion {
    static constexpr int kMaxSamples = 65536;
    int samples = 16;         // in [1, kMaxSamples]
    double distance = 1e30;   // > 0
    double min_amount = 0;    // in [0, 1]
};

// Ambient light: incident radiance ls * color everywhere
// (times the visible fraction, with Scene::ambient_occlusion).
struct AmbientLight {
    Vec3d color{1, 1, 1};
    double ls = 1.0;
};

enum class Attenuation { none, inverse_square };
inline constexpr const char* kAttenuationNames[] = {"none", "inverse_square"};
inline constexpr const char* attenuation_name(Attenuation a) { return kAttenuationNames[static_cast<int>(a)]; }

// Directional light. `direction` points from the surface toward the light
// (the shading model's l is unit_direction(direction)).
struct DirectionalLight {
    Vec3d direction{0, 1, 0};
    Vec3d color{1, 1, 1};
    double ls = 1.0;
    bool shadows = false;
};

// Point light; 1/r^2 only with Attenuation::inverse_square.
struct PointLight {
    Vec3d position{0, 0, 0};
    Vec3d color{1, 1, 1};
    double ls = 1.0;
    Attenuation attenuation = Attenuation::none;
    bool shadows = false;
};

struct Sphere { Vec3d center; double radius = 1; };
struct Plane { Vec3d point; Vec3d normal{0, 1, 0}; };           // normal: any length
struct Disk { Vec3d center; Vec3d normal{0, 1, 0}; double radius = 1; };
struct Rectangle { Vec3d corner; Vec3d a{1, 0, 0}; Vec3d b{0, 1, 0}; };  // corner + s*a + t*b, s,t in [0,1]
struct Box { Vec3d min; Vec3d max{1, 1, 1}; };                   // axis-aligned, min < max
struct Triangle { Vec3d v0, v1{1, 0, 0}, v2{0, 1, 0}; };

using Shape = std::variant<Sphere, Plane, Disk, Rectangle, Box, Triangle>;

enum class PrimitiveType { sphere = 0, plane, disk, rectangle, box, triangle };
inline constexpr int kPrimitiveTypeCount = 6;
inline constexpr const char* kPrimitiveTypeNames[kPrimitiveTypeCount] = {"sphere", "plane", "disk",
                                                                          "rectangle", "box", "triangle"};
inline constexpr const char* primitive_type_name(PrimitiveType t) { return kPrimitiveTypeNames[static_cast<int>(t)]; }
inline PrimitiveType primitive_type(const Shape& s) { return static_cast<PrimitiveType>(s.index()); }

struct Object {
    Shape shape;
    int material = 0;  // index into Scene::materials
};

// A triangle mesh (docs/scene-format.md, meshes): shared vertices and 32-bit indices,
// three per triangle, each < vertices.size(); every triangle is one primitive
// of PrimitiveType::triangle, with the watertight test of a single triangle.
// No zero-area triangle (the model loader drops and counts them).
struct Mesh {
    std::vector<Vec3d> vertices;
    std::vector<std::uint32_t> indices;
    int material = 0;                    // index into Scene::materials
    std::size_t dropped_degenerate = 0;  // zero-area triangles the loader left out (information only)
    std::size_t triangle_count() const { return indices.size() / 3; }
};

enum class ToneMap { max_to_one, clamp_to_color, saturate };
inline constexpr const char* kToneMapNames[] = {"max_to_one", "clamp_to_color", "saturate"};
inline constexpr const char* tonemap_name(ToneMap t) { return kToneMapNames[static_cast<int>(t)]; }

struct RenderSettings {
    ToneMap tonemap = ToneMap::max_to_one;
    Vec3d clamp_color{1, 0, 0};  // a display colour: components in [0, 1]
    double gamma = 1.0;  // > 0; display colour is c^(1/gamma)
};

// Limits (validate() enforces them; the JSON loader reports them at their path).
// Primitive and material ids travel through the kernels as exact floats, so a
// scene has fewer than 2^24 of each. The image side bounds the render's memory:
// `octray render` holds about 31 bytes a pixel (HDR, display, ids; 6.1 GB peak
// at 16384 x 12288).
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::size_t kMaxPrimitives = (std::size_t(1) << 24) - 1;  // objects and mesh triangles
inline constexpr std::size_t kMaxMaterials = (std::size_t(1) << 24) - 1;

struct Scene {
    Camera camera;
    Vec3d background{0, 0, 0};
    std::optional<AmbientLight> ambient;  // absent: no ambient light
    // The JSON's ambient.occlusion; needs `ambient`. Absent: the constant ambient light.
    std::optional<AmbientOcclusion> ambient_occlusion;
    std::vector<DirectionalLight> directional_lights;
    std::vector<PointLight> point_lights;
    std::vector<Material> materials;
    std::vector<Object> objects;  // primitive id = position here
    // Mesh triangles' primitive ids follow the objects': objects.size() +
    // the triangle's position in the meshes' triangles, mesh after mesh.
    std::vector<Mesh> meshes;
    RenderSettings render;

    std::size_t mesh_triangle_count() const {
        std::size_t n = 0;
        for (const Mesh& m : meshes) n += m.triangle_count();
        return n;
    }
};

// The unit vector along a scene direction, v / |v|: the one normalization
// every path applies to DirectionalLight::direction, Plane::normal,
// Disk::normal and Camera::up. v is first scaled by a power of two (exact), so
// components near 1e300 or 1e-300 neither overflow nor underflow; where v.v
// does neither anyway, the result is bit for bit v / sqrt(v.v). NaN
// components for a zero or non-finite v, which validate() rejects.
Vec3d unit_direction(const Vec3d& v);

// What validate() throws: what() is "PATH: PROBLEM", e.g.
// "objects[3].radius: must be > 0, got -1"; path() and problem() are the two
// parts (the JSON loader reports problem() at the file's path for path()).
class InvalidScene : public std::invalid_argument {
public:
    InvalidScene(const std::string& path, const std::string& problem);
    std::string path() const;
    std::string problem() const;

private:
    std::size_t path_size_;
};

// The one set of scene rules: checks the invariants above, on a scene built in
// code and on every scene the JSON loader reads (it judges value ranges by
// this function alone). Throws InvalidScene (a std::invalid_argument) naming
// the first offending field, e.g. "objects[3].material: index 7, but there are
// 2 materials". compile() calls it, so the kernels only ever see valid scenes.
// Degenerate means, scale-free: a camera `up` within a sine of 1e-6 of the
// view direction; rectangle edges a, b with |a x b| < 1e-9 |a||b|; a triangle
// with |(v1 - v0) x (v2 - v0)| < 1e-9 times its longest edge squared.
void validate(const Scene& scene);

}  // namespace octray
