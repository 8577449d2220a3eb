// io/model_formats.hpp — the three model-file readers behind load_model (model_loader.hpp),
// one per format, each over a file's bytes already in memory. Internal to io/.
//
// Every reader is compiled into octray's own units, so the sanitizer and fuzz builds see
// into all of it (docs/reliability.md):
//   read_ply   ply_reader.cpp   octray's own: ASCII, binary little- and big-endian
//   read_obj   obj_reader.cpp   tinyobjloader (Debian's libtinyobjloader-dev, header-only)
//   read_gltf  gltf_reader.cpp  tinygltf (Debian's libtinygltf-dev, header-only)
//
// The contract of each reader:
// - Every count the file states is checked against the bytes that could hold it before
//   anything of that size is allocated, so memory stays bounded by a small multiple of the
//   input's size (instancing in glTF aside, which kMaxModelTriangles bounds).
// - Every index is checked < positions.size(); polygons are fanned into triangles
//   (v0, vi, vi+1) in the file's winding; points and lines are left out.
// - Problems are ModelError with a short lower-case one-line message, never a crash, an
//   abort or another exception type (std::bad_alloc included: readers catch it).
// - Positions are returned as read, not checked for finiteness: collect_model() does that.
#pragma once

#include "model_loader.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace octray::model_formats {

// One mesh of a file: its positions and its triangles, three indices each.
struct RawMesh {
    std::string name;               // may be empty; used in messages ("mesh 2 'wheel': ")
    std::vector<Vec3d> positions;
    std::vector<std::uint32_t> triangles;
};

// One use of a mesh under a transform (a glTF node's global matrix). OBJ and PLY files
// have one identity instance per mesh.
struct RawInstance {
    std::uint32_t mesh = 0;
    Matrix4d transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

struct RawModel {
    std::vector<RawMesh> meshes;
    std::vector<RawInstance> instances;

    // One identity instance per mesh (OBJ, PLY).
    void instance_each_mesh();
};

RawModel read_ply(std::string_view bytes);
RawModel read_obj(std::string_view bytes);
// binary: a .glb container, else .gltf JSON. External buffers are read from `base_dir`
// (the model file's folder) only: a URI that is absolute or leaves that folder is refused,
// as is one whose file is larger than kMaxModelFileBytes. Images are never read.
RawModel read_gltf(std::string_view bytes, bool binary, const std::filesystem::path& base_dir);

// The common tail of load_model: every instance's mesh under user·instance transform, in
// double; finiteness checked; vertices shared by exact position; zero-area triangles
// dropped and counted; kMaxModelTriangles checked before anything is built.
MeshData collect_model(const RawModel& model, const Matrix4d& user, const char* format);

// Called in a reader's catch (...): a ModelError goes on as it is, std::bad_alloc becomes
// "out of memory reading the model", any other std::exception "unreadable <format>: ...".
[[noreturn]] void rethrow_as_model_error(const char* format);

// "mesh 2 'wheel': " when the model has several meshes, else "".
std::string mesh_prefix(const RawModel& model, std::size_t m);

}  // namespace octray::model_formats
