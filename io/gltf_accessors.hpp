// io/gltf_accessors.hpp — reading a glTF primitive's geometry out of tinygltf's buffers
// (io/gltf_accessors.cpp), for io/gltf_reader.cpp. Khronos, "glTF 2.0 Specification",
// accessors §3.6, meshes §3.7.
#pragma once

#include "model_formats.hpp"

#include <nlohmann/json.hpp>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_JSON
#include <tiny_gltf.h>  // a system header (CMake): its own warnings are not ours

#include <cstdint>
#include <string>
#include <vector>

namespace octray::model_formats::gltf {

[[noreturn]] inline void unreadable(const std::string& why) { throw ModelError("unreadable glTF: " + why); }

// The accessor's positions (VEC3 of float), sparse substitution applied; every range is
// checked against its buffer view and buffer before an element is copied.
std::vector<Vec3d> read_positions(const tinygltf::Model& model, int index);

// The primitive's vertex order: its index accessor (unsigned byte, short or int), or
// 0, 1, 2, ... without one.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                        std::size_t vertex_count);

// Triangles from the primitive's vertex order by its mode; every index checked.
void triangulate(const std::vector<std::uint32_t>& order, int mode, RawMesh& mesh, const std::string& what);

// Triangles, strips and fans; points and lines are left out.
bool has_triangles(int mode);

}  // namespace octray::model_formats::gltf
