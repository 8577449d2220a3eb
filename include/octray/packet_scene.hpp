// octray/packet_scene.hpp — a scene compiled for the packet kernels.
//
// compile() turns the authoring Scene (AoS, double) into the layout the
// kernels read (structure of arrays in float, with the culling structure);
// the layout is the library's own and may change between versions. A
// PacketScene is immutable: copies share its data, and any number of threads
// may use one at once.
#pragma once

#include <octray/features.hpp>
#include <octray/scene.hpp>

#include <memory>

namespace octray {

struct SceneData;    // kernels/scene_data.hpp (internal)
struct SceneAccess;  // the kernels' view of a PacketScene (internal)

// The binned-SAH build's parameters (Wald 2007): at most max_leaf_size
// primitives a leaf (1..255), SAH bins per axis (2..64), the SAH costs of
// visiting a binary node (finite, >= 0) and of testing a block of leaf_block
// primitives (finite, > 0), and that block (1..255: the primitives one ray
// tests at once, side by side in the lanes). Start from a preset; no value
// changes an image, only how fast the scene is built and traced.
struct SahOptions {
    int max_leaf_size = 8;
    int bins = 16;
    float traversal_cost = 2.0f;
    float intersection_cost = 1.0f;
    int leaf_block = 8;

    // The defaults: what compile() uses unless told otherwise.
    static SahOptions balanced() noexcept { return {}; }
    // Half the bins: less work a split, so a shorter build.
    static SahOptions fast_build() noexcept {
        SahOptions o;
        o.bins = 8;
        return o;
    }
    // Twice the bins: split positions looked at more finely, for a longer build.
    static SahOptions high_quality() noexcept {
        SahOptions o;
        o.bins = 32;
        return o;
    }
};

// How compile() builds the acceleration structure over the bounded
// primitives (every type but planes). A value: compile() reads it, keeps
// nothing, and no option changes an image: only how fast it is made.
// (The pragmas: the implicit constructors copy the deprecated fields; only a
// caller's own use of one should warn.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
struct CompileOptions {
    enum class Acceleration {
        bvh,   // an 8-wide BVH by binned SAH: a walk skips what a ray cannot hit
        none,  // the same tree with every child's box infinite: every ray tests
               // every bounded primitive (a baseline for tests and benchmarks)
    };
    Acceleration acceleration = Acceleration::bvh;
    // Threads for the build (octray/threads.hpp: 0 = every core; >= 0). The
    // tree is the same whatever the count.
    int threads = 0;
    SahOptions sah = SahOptions::balanced();

    // Deprecated (octray 0.1's names; removed in 0.3): sah's fields, as
    // they were before they were grouped. One that differs from its default
    // is used in place of sah's.
    [[deprecated("use CompileOptions::sah.max_leaf_size")]] int max_leaf_size = 8;
    [[deprecated("use CompileOptions::sah.bins")]] int bins = 16;
    [[deprecated("use CompileOptions::sah.traversal_cost")]] float traversal_cost = 2.0f;
    [[deprecated("use CompileOptions::sah.intersection_cost")]] float intersection_cost = 1.0f;
    [[deprecated("use CompileOptions::sah.leaf_block")]] int leaf_block = 8;
};
#pragma GCC diagnostic pop

class PacketScene {
  public:
    PacketScene();  // a scene with nothing in it

    const Features& features() const noexcept;
    int count(PrimitiveType type) const noexcept;  // primitives of one type
    int primitive_count() const noexcept;
    int width() const noexcept;   // the camera's image size
    int height() const noexcept;

  private:
    std::shared_ptr<SceneData> data_;
    friend PacketScene compile(const Scene& scene, const CompileOptions& options);
    friend struct SceneAccess;
};

// Deprecated (removed in octray 0.3): PacketScene::data(), the kernels'
// internal layout, which no public header defines.
[[deprecated("the kernels' internal layout is not part of the API; removed in octray 0.3")]]
const SceneData& packet_scene_data(const PacketScene& scene) noexcept;

// Compiles a scene. Throws std::invalid_argument when validate() rejects it or
// it has 2^24 or more primitives (objects and mesh triangles) or materials
// (ids travel as exact floats), or when `options` are out of range.
PacketScene compile(const Scene& scene, const CompileOptions& options = {});

}  // namespace octray
