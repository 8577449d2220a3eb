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

struct SceneData;  // kernels/scene_data.hpp (internal)

// How compile() builds the acceleration structure over the bounded
// primitives (every type but planes). A value: compile() reads it, keeps
// nothing, and no option changes an image: only how fast it is made.
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
    // The build's parameters: at most max_leaf_size primitives a leaf
    // (1..255), SAH bins per axis (2..64), the SAH costs of visiting a
    // binary node (finite, >= 0) and of testing a block of leaf_block
    // primitives (finite, > 0), and that block (1..255: the primitives one
    // ray tests at once, side by side in the lanes).
    int max_leaf_size = 8;
    int bins = 16;
    float traversal_cost = 2.0f;
    float intersection_cost = 1.0f;
    int leaf_block = 8;
};

class PacketScene {
  public:
    PacketScene();  // a scene with nothing in it

    const Features& features() const noexcept;
    int count(PrimitiveType type) const noexcept;  // primitives of one type
    int primitive_count() const noexcept;
    int width() const noexcept;   // the camera's image size
    int height() const noexcept;

    // The kernels' view (internal layout).
    const SceneData& data() const noexcept { return *data_; }

  private:
    std::shared_ptr<SceneData> data_;
    friend PacketScene compile(const Scene& scene, const CompileOptions& options);
};

// Compiles a scene. Throws std::invalid_argument when validate() rejects it or
// it has 2^24 or more primitives (objects and mesh triangles) or materials
// (ids travel as exact floats), or when `options` are out of range.
PacketScene compile(const Scene& scene, const CompileOptions& options = {});

}  // namespace octray
