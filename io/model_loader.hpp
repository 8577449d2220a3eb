// io/model_loader.hpp — triangle meshes from model files (glTF 2.0, OBJ, PLY) for the
// scene JSON's "mesh" object (docs/scene-format.md, "Meshes").
//
// load_model() reads every triangle of a file (polygons triangulated, glTF node transforms
// applied first), applies a MeshTransform in double, checks the result and returns an
// indexed triangle list. Every problem is a ModelError with a short lower-case message of
// what is wrong; the caller adds the scene file and the JSON path. The readers, one per
// format, are in model_formats.hpp: tinygltf, tinyobjloader and octray's own PLY reader,
// all compiled into octray's units so the sanitizer and fuzz builds see into them.
#pragma once

#include <octray/scene.hpp>
#include <octray/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace octray {

class ModelError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A 4x4 matrix, row-major: element (r, c) is m[4*r + c]; a point p maps to M·(p, 1).
using Matrix4d = std::array<double, 16>;

// Limits, checked before anything of their size is built:
// - each file read for a model (the model itself, a glTF's external buffers) may be at
//   most kMaxModelFileBytes; a larger one is refused unread. OBJ material libraries and
//   images are never opened.
// - a model may have at most kMaxModelTriangles triangles, counted after glTF instancing
//   (a mesh used by n nodes counts n times) and before degenerate ones are dropped: a
//   scene's limit on primitives (scene.hpp), since a larger model could not be compiled.
inline constexpr std::uint64_t kMaxModelFileBytes = std::uint64_t(2) << 30;  // 2 GiB
inline constexpr std::uint64_t kMaxModelTriangles = kMaxPrimitives;

// The "transform" of a mesh object: translate, rotate_deg (about x, then y, then z, in
// degrees), uniform scale, applied as scale, then rotate, then translate; or a 4x4
// row-major affine matrix instead of those three. The default is the identity.
struct MeshTransform {
    Vec3d translate{0, 0, 0};
    Vec3d rotate_deg{0, 0, 0};
    double scale = 1;
    std::optional<Matrix4d> matrix;  // when set, translate/rotate_deg/scale are not used

    static MeshTransform from_trs(const Vec3d& translate, const Vec3d& rotate_deg, double scale);
    static MeshTransform from_matrix(const Matrix4d& m);

    // The 4x4 matrix: `matrix` itself, or T·Rz·Ry·Rx·S. Rotations by whole multiples of
    // 90 degrees use exact sines and cosines (0, ±1), so they permute coordinates exactly.
    Matrix4d to_matrix() const;

    // The first problem of this transform, as "field: what is wrong" (for example
    // "scale: must be > 0, got -1"), or an empty string when it is valid.
    std::string problem() const;
};

// Validation helpers, one per field of the JSON contract; each returns an empty string when
// the value is valid, else a short lower-case description of what is wrong.
std::string translate_problem(const Vec3d& t);       // finite
std::string rotate_deg_problem(const Vec3d& r);      // finite
std::string scale_problem(double s);                 // finite and > 0
// Finite; affine (last row exactly 0 0 0 1); invertible: the 3x3 part, each row scaled to
// unit length, has |det| > 1e-12 (a scale-free test: 1 for a rotation, 0 when singular).
std::string matrix_problem(const Matrix4d& m);

// An indexed triangle list: triangle t is vertices[indices[3t]], [3t+1], [3t+2], in the
// file's winding. Vertices with bitwise-equal positions (after the transform, across all
// meshes of the file) are one vertex; every vertex is used by at least one triangle.
struct MeshData {
    std::vector<Vec3d> vertices;
    std::vector<std::uint32_t> indices;
    std::size_t dropped_degenerate = 0;  // zero-area triangles left out (see load_model)
    std::string format;                  // "glTF 2.0", "Wavefront OBJ", "PLY", "generated"
    // Where each kept triangle stood among the file's, before the zero-area
    // ones were dropped (the numbering a caller's own face array has: the
    // Python module reports it as primitive_id). Empty when none was dropped:
    // then triangle t is the file's triangle t, and a large model pays nothing.
    std::vector<std::uint32_t> faces;

    std::size_t triangle_count() const { return indices.size() / 3; }
    // The file's number of triangle t (see faces).
    std::uint32_t face_of(std::size_t t) const { return faces.empty() ? std::uint32_t(t) : faces[t]; }
};

// Reads the model file at `path`. The format comes from the extension (.gltf, .glb, .obj,
// .ply, any case); the file must really be of that format. All meshes of the file are
// concatenated: for glTF each mesh once per node that uses it, under that node's global
// transform; points and lines are left out. Each vertex maps to transform·node·p in double.
//
// A triangle is degenerate, and dropped and counted, when the cross product of its two
// edges, computed in double from the transformed vertices, is exactly (0, 0, 0): repeated
// vertices and exactly collinear ones. No relative epsilon: a thin but real triangle stays.
// The file's triangles are numbered in this order (meshes, glTF instances in node order,
// polygons as triangulated), counting the dropped ones: MeshData::faces.
//
// Throws ModelError, for example: "cannot open: No such file or directory",
// "unknown model format '.stl' (expected .gltf, .glb, .obj or .ply)",
// "unreadable glTF: <what is wrong>", "vertex 12 is not finite: (nan, 0, 1)",
// "face 3: index 99 out of range (40 vertices)", "no triangles",
// "too many triangles: ... (limit 67108864)", "transform: scale: ...".
MeshData load_model(const std::string& path, const MeshTransform& transform = {});

// Writes `mesh` as a binary little-endian PLY. PLY stores float:
// each vertex is rounded to float, and a vertex that does not fit (non-finite after the
// rounding) is a ModelError, as is a mesh with no triangle or an index out of range.
void save_ply(const MeshData& mesh, const std::string& path);

}  // namespace octray
