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
    friend PacketScene compile(const Scene& scene);
    friend SceneData& mutable_data(PacketScene& scene);
};

// Compiles a scene. Throws std::invalid_argument when validate() rejects it or
// it has 2^24 or more primitives (objects and mesh triangles) or materials
// (ids travel as exact floats).
PacketScene compile(const Scene& scene);

}  // namespace octray
