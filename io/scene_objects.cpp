// io/scene_objects.cpp — the scene JSON's objects: shapes, and meshes read
// from model files (model_loader.hpp) under their transforms.
#include "scene_reader.hpp"

#include "model_loader.hpp"

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <numeric>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

// The folders searched for a relative model path when OCTRAY_MODEL_PATH is
// unset: colon-separated, set by CMakeLists.txt (assimp-testmodels' folder
// where the build found it), else empty.
#ifndef OCTRAY_DEFAULT_MODEL_PATH
#define OCTRAY_DEFAULT_MODEL_PATH ""
#endif

namespace octray::scene_json {

namespace {

std::vector<std::string> split_path_list(const std::string& list) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t end = std::min(list.find(':', start), list.size());
        if (end > start) out.push_back(list.substr(start, end - start));  // empty entries are skipped
        start = end + 1;
    }
    return out;
}

// The places a mesh's "file" may be, in order (docs/scene-format.md, "Model
// paths"): an absolute path as given; a relative one in the scene file's
// folder, then in each folder of OCTRAY_MODEL_PATH (colon-separated), or of
// the build's default list when that variable is unset.
// base_dir: the scene file's folder (or the base directory of a scene held in
// memory), "" or ending in '/'.
std::vector<std::string> model_candidates(const std::string& base_dir, const std::string& file) {
    if (!file.empty() && file[0] == '/') return {file};
    std::vector<std::string> out{base_dir + file};
    const char* env = std::getenv("OCTRAY_MODEL_PATH");
    for (const std::string& dir : split_path_list(env ? env : OCTRAY_DEFAULT_MODEL_PATH))
        out.push_back(dir.back() == '/' ? dir + file : dir + "/" + file);
    return out;
}

}  // namespace

Shape Reader::shape(const Json& o, const std::string& path, PrimitiveType type) const {
    const std::string what = std::string("a ") + primitive_type_name(type);
    auto req = [&](const char* key) -> const Json& { return required(o, path, key, what); };
    auto vec = [&](const char* key) { return vec3(req(key), member(path, key)); };
    auto radius = [&] { return number(req("radius"), member(path, "radius")); };
    switch (type) {
        case PrimitiveType::sphere: {
            Sphere s;
            s.center = vec("center");
            s.radius = radius();
            return s;
        }
        case PrimitiveType::plane: return Plane{vec("point"), vec("normal")};
        case PrimitiveType::disk: {
            Disk d;
            d.center = vec("center");
            d.normal = vec("normal");
            d.radius = radius();
            return d;
        }
        case PrimitiveType::rectangle: return Rectangle{vec("corner"), vec("a"), vec("b")};
        case PrimitiveType::box: return Box{vec("min"), vec("max")};
        case PrimitiveType::triangle: {
            const std::string vpath = member(path, "vertices");
            const Json& vs = req("vertices");
            if (!vs.is_array() || vs.size() != 3)
                fail(vpath, "must be an array of 3 points ([x,y,z]), got " + describe(vs));
            return Triangle{vec3(vs[0], element(vpath, 0)), vec3(vs[1], element(vpath, 1)), vec3(vs[2], element(vpath, 2))};
        }
    }
    fail(path, "internal error: unhandled primitive type");
}

// A mesh object (docs/scene-format.md, meshes): its model file read by load_model.
Mesh Reader::mesh(const Json& o, const std::string& opath, std::vector<std::uint32_t>& faces) const {
    reject_unknown(o, opath, "a mesh", {"type", "file", "material", "transform"});
    const std::string fpath = member(opath, "file");
    const std::string file = string(required(o, opath, "file", "a mesh"), fpath);
    MeshTransform transform;
    if (auto* v = optional(o, "transform")) transform = mesh_transform(*v, member(opath, "transform"));
    // The first candidate that exists; none: the first one's error, and every place looked in.
    const std::vector<std::string> candidates = model_candidates(base_dir_, file);
    std::string resolved;
    for (const std::string& c : candidates) {
        std::error_code ec;
        if (std::filesystem::exists(c, ec)) {
            resolved = c;
            break;
        }
    }
    if (resolved.empty() && !file.empty() && file[0] != '/') {
        std::string tried;
        for (const std::string& c : candidates) tried += (tried.empty() ? "" : ", ") + c;
        fail(fpath, file + ": cannot open: No such file or directory (tried " + tried + ")");
    }
    if (resolved.empty()) resolved = candidates.front();  // an absolute path: load_model says why it cannot open it
    try {
        MeshData data = load_model(resolved, transform);
        Mesh m;
        m.vertices = std::move(data.vertices);
        m.indices = std::move(data.indices);
        m.dropped_degenerate = data.dropped_degenerate;
        faces = std::move(data.faces);
        return m;
    } catch (const ModelError& e) {
        fail(fpath, file + ": " + e.what());
    }
}

Mesh Reader::mesh_at(const Json& o, const std::string& opath, std::size_t index,
                     std::vector<std::uint32_t>& faces) const {
    const auto it = arrays_ ? arrays_->find(index) : decltype(arrays_->end()){};
    if (!arrays_ || it == arrays_->end()) return mesh(o, opath, faces);
    reject_unknown(o, opath, "a mesh given as arrays", {"type", "vertices", "indices", "material", "transform"});
    required(o, opath, "vertices", "a mesh given as arrays");
    required(o, opath, "indices", "a mesh given as arrays");
    Mesh m;
    m.vertices = it->second.vertices;
    m.indices = it->second.indices;
    if (auto* v = optional(o, "transform")) {
        const Matrix4d t = mesh_transform(*v, member(opath, "transform")).to_matrix();
        for (Vec3d& p : m.vertices)
            p = {t[0] * p.x + t[1] * p.y + t[2] * p.z + t[3], t[4] * p.x + t[5] * p.y + t[6] * p.z + t[7],
                 t[8] * p.x + t[9] * p.y + t[10] * p.z + t[11]};
    }
    drop_zero_area(m, faces, opath);
    return m;
}

// Zero-area triangles of a mesh given as arrays, dropped and counted as
// collect_model drops a model file's (the same test: an exactly zero cross
// product of the transformed edges), so an array mesh behaves as the same
// mesh saved to a file. Only where every index is in range and every vertex
// finite: otherwise validate() reports the first bad one at its position in
// the caller's arrays, which dropping would shift.
void Reader::drop_zero_area(Mesh& m, std::vector<std::uint32_t>& faces, const std::string& opath) const {
    const std::size_t n = m.vertices.size();
    if (m.indices.size() % 3 != 0) return;
    for (const Vec3d& v : m.vertices)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return;
    for (const std::uint32_t i : m.indices)
        if (i >= n) return;
    std::size_t kept = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const std::uint32_t* tri = &m.indices[3 * t];
        const Vec3d& a = m.vertices[tri[0]];
        const Vec3d e = cross(m.vertices[tri[1]] - a, m.vertices[tri[2]] - a);
        if (e.x == 0 && e.y == 0 && e.z == 0) {
            if (faces.empty()) {  // the first drop: those kept so far keep their numbers
                faces.resize(kept);
                std::iota(faces.begin(), faces.end(), std::uint32_t(0));
            }
            ++m.dropped_degenerate;
            continue;
        }
        if (m.dropped_degenerate) faces.push_back(std::uint32_t(t));
        std::copy_n(tri, 3, &m.indices[3 * kept++]);
    }
    if (m.dropped_degenerate && kept == 0)
        fail(member(opath, "indices"), "no triangles (all " + std::to_string(m.dropped_degenerate) + " have zero area)");
    m.indices.resize(3 * kept);
}

MeshTransform Reader::mesh_transform(const Json& j, const std::string& path) const {
    expect_object(j, path);
    reject_unknown(j, path, "a transform", {"translate", "rotate_deg", "scale", "matrix"});
    MeshTransform t;
    auto check = [&](const std::string& key, const std::string& problem) {
        if (!problem.empty()) fail(member(path, key), problem);
    };
    if (auto* v = optional(j, "matrix")) {
        for (const char* key : {"translate", "rotate_deg", "scale"})
            if (optional(j, key)) fail(member(path, key), "not with \"matrix\": give one or the other");
        const std::string mpath = member(path, "matrix");
        if (!v->is_array() || v->size() != 16) fail(mpath, "must be an array of 16 numbers (row-major), got " + describe(*v));
        Matrix4d m{};
        for (std::size_t i = 0; i < 16; ++i) m[i] = number((*v)[i], element(mpath, i));
        check("matrix", matrix_problem(m));
        return MeshTransform::from_matrix(m);
    }
    if (auto* v = optional(j, "translate")) t.translate = vec3(*v, member(path, "translate")), check("translate", translate_problem(t.translate));
    if (auto* v = optional(j, "rotate_deg")) t.rotate_deg = vec3(*v, member(path, "rotate_deg")), check("rotate_deg", rotate_deg_problem(t.rotate_deg));
    if (auto* v = optional(j, "scale")) t.scale = number(*v, member(path, "scale")), check("scale", scale_problem(t.scale));
    return t;
}

std::vector<Object> Reader::objects(const Json& j, const std::string& path, const std::vector<Material>* mats,
                            std::vector<Mesh>& meshes, SourceMap& source) const {
    if (!j.is_array()) fail(path, "must be an array, got " + describe(j));
    static const std::vector<Names> fields{
        {"type", "center", "radius", "material"},         {"type", "point", "normal", "material"},
        {"type", "center", "normal", "radius", "material"}, {"type", "corner", "a", "b", "material"},
        {"type", "min", "max", "material"},               {"type", "vertices", "material"}};
    Names material_names;
    if (mats)
        for (const auto& m : *mats) material_names.push_back(m.name);

    std::vector<Object> out;
    // The primitive limit (scene.hpp) checked as meshes come in, before a
    // scene too large to compile loads more models.
    std::size_t primitives = 0;
    auto count = [&](std::size_t n, const std::string& at) {
        primitives += n;
        if (primitives > kMaxPrimitives)
            fail(at, "too many primitives: more than " + std::to_string(kMaxPrimitives) +
                         " objects and mesh triangles (the limit)");
    };
    for (std::size_t i = 0; i < j.size(); ++i) {
        const Json& o = j[i];
        const std::string opath = element(path, i);
        Names types = names_of(kPrimitiveTypeNames);
        types.push_back("mesh");
        const std::size_t type_index = type_of(o, opath, "object", types);
        const bool is_mesh = type_index == std::size_t(kPrimitiveTypeCount);
        const auto type = static_cast<PrimitiveType>(is_mesh ? 0 : type_index);
        const std::string what = is_mesh ? std::string("a mesh") : std::string("a ") + primitive_type_name(type);
        Object obj;
        Mesh m;
        std::vector<std::uint32_t> faces;
        if (is_mesh) {
            m = mesh_at(o, opath, i, faces);
            count(m.triangle_count(), member(opath, optional(o, "file") ? "file" : "indices"));
        } else {
            count(1, opath);
            reject_unknown(o, opath, what, fields[static_cast<std::size_t>(type)]);
            obj.shape = shape(o, opath, type);
        }
        // A scene without materials (geometry-only) gives each object the
        // placeholder, material 0, unless it names one (which is unknown).
        int material = 0;
        const std::string mpath = member(opath, "material");
        if (mats || optional(o, "material")) {
            const std::string name = string(required(o, opath, "material", what), mpath);
            auto it = std::find(material_names.begin(), material_names.end(), name);
            if (it == material_names.end())
                fail(mpath, "unknown material \"" + name + "\" (" +
                                (material_names.empty() ? std::string("no materials are defined")
                                                        : "defined: " + join(material_names)) +
                                ")");
            material = static_cast<int>(it - material_names.begin());
        }
        if (is_mesh) {
            m.material = material;
            meshes.push_back(std::move(m));
            source.mesh.push_back(i);
            source.faces.push_back(std::move(faces));
            continue;
        }
        obj.material = material;
        out.push_back(std::move(obj));
        source.object.push_back(i);
    }
    return out;
}

}  // namespace octray::scene_json
