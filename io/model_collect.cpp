// io/model_collect.cpp — collect_model (model_formats.hpp): what every reader's RawModel
// becomes on its way to a MeshData. All arithmetic in double.
#include "model_formats.hpp"

#include "model_math.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <numeric>
#include <vector>

namespace octray::model_formats {

using namespace model_math;

void RawModel::instance_each_mesh() {
    instances.clear();
    instances.reserve(meshes.size());
    for (std::size_t m = 0; m < meshes.size(); ++m) instances.push_back(RawInstance{static_cast<std::uint32_t>(m)});  // identity
}

std::string mesh_prefix(const RawModel& model, std::size_t m) {
    if (model.meshes.size() <= 1) return "";
    std::string p = "mesh " + std::to_string(m);
    if (!model.meshes[m].name.empty()) p += " '" + model.meshes[m].name + "'";
    return p + ": ";
}

void rethrow_as_model_error(const char* format) {
    try {
        throw;
    } catch (const ModelError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw ModelError("out of memory reading the model");
    } catch (const std::exception& e) {
        throw ModelError(std::string("unreadable ") + format + ": " + e.what());
    }
}

namespace {

Vec3d transform_point(const Matrix4d& m, const Vec3d& p) {
    return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

struct PositionKey {
    std::uint64_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
PositionKey key_of(const Vec3d& p) {
    auto bits = [](double v) {
        v += 0.0;  // -0 and +0 are one position
        std::uint64_t b;
        std::memcpy(&b, &v, sizeof b);
        return b;
    };
    return {bits(p.x), bits(p.y), bits(p.z)};
}

std::uint64_t hash_of(const PositionKey& k) {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= (k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2)) * 0xC2B2AE3D27D4EB4Full;
    h ^= (k.z + 0x165667B19E3779F9ull + (h << 6) + (h >> 2)) * 0x9E3779B97F4A7C15ull;
    return h ^ (h >> 29);
}

// The output's vertices, one per position (compared by key_of's bits): an
// open-addressing table of indices into them, linear probing, at most half
// full. A node-based map cost an allocation per vertex, most of a large
// model's load.
class SharedVertices {
  public:
    SharedVertices(std::vector<Vec3d>& vertices, std::size_t expected) : vertices_(vertices) {
        std::size_t size = 16;
        while (size < 2 * expected) size *= 2;
        slots_.assign(size, kEmpty);
    }
    // The index of p among the vertices, appended when its position is new.
    std::uint32_t index_of(const Vec3d& p) {
        if (2 * (vertices_.size() + 1) > slots_.size()) grow();
        const PositionKey key = key_of(p);
        const std::size_t mask = slots_.size() - 1;
        for (std::size_t i = hash_of(key) & mask;; i = (i + 1) & mask) {
            const std::uint32_t s = slots_[i];
            if (s == kEmpty) {
                slots_[i] = static_cast<std::uint32_t>(vertices_.size());
                vertices_.push_back(p);
                return slots_[i];
            }
            if (key_of(vertices_[s]) == key) return s;
        }
    }

  private:
    static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
    void grow() {
        slots_.assign(slots_.size() * 2, kEmpty);
        const std::size_t mask = slots_.size() - 1;
        for (std::uint32_t v = 0; v < vertices_.size(); ++v) {
            std::size_t i = hash_of(key_of(vertices_[v])) & mask;
            while (slots_[i] != kEmpty) i = (i + 1) & mask;
            slots_[i] = v;
        }
    }
    std::vector<Vec3d>& vertices_;
    std::vector<std::uint32_t> slots_;
};

// The raw meshes' own checks, before anything is built: indices in range (each reader
// promises it; checked again here, cheaply, as the last wall), the vertices of every mesh
// that has triangles finite, the instanced triangle count within the limit.
void check_raw(const RawModel& model) {
    for (std::size_t m = 0; m < model.meshes.size(); ++m) {
        const RawMesh& mesh = model.meshes[m];
        if (mesh.triangles.size() % 3 != 0) throw ModelError(mesh_prefix(model, m) + "broken triangle list");
        for (const std::uint32_t i : mesh.triangles)
            if (i >= mesh.positions.size())
                throw ModelError(mesh_prefix(model, m) + "index " + std::to_string(i) + " out of range (" +
                                 std::to_string(mesh.positions.size()) + " vertices)");
        if (mesh.triangles.empty()) continue;
        for (std::size_t v = 0; v < mesh.positions.size(); ++v)
            if (!finite3(mesh.positions[v]))
                throw ModelError(mesh_prefix(model, m) + "vertex " + std::to_string(v) +
                                 " is not finite: " + vec_str(mesh.positions[v]));
    }
    std::uint64_t total = 0;
    for (const RawInstance& use : model.instances) {
        if (use.mesh >= model.meshes.size())
            throw ModelError("instance of mesh " + std::to_string(use.mesh) + " of " +
                             std::to_string(model.meshes.size()));
        total += model.meshes[use.mesh].triangles.size() / 3;
        if (total > kMaxModelTriangles)
            throw ModelError("too many triangles: more than " + std::to_string(kMaxModelTriangles) + " (the limit)");
    }
    if (total == 0) throw ModelError("no triangles");
}

}  // namespace

MeshData collect_model(const RawModel& model, const Matrix4d& user, const char* format) {
    check_raw(model);
    MeshData out;
    out.format = format;
    // An instance costs its mesh's triangles, never its vertex count: the
    // per-vertex state is allocated once, for the largest mesh, and only the
    // vertices an instance touched are reset after it (a mesh of many vertices
    // and few triangles, used by many nodes, stays cheap).
    std::size_t positions = 0, indices = 0, largest = 0;
    for (const RawInstance& use : model.instances) {
        const RawMesh& mesh = model.meshes[use.mesh];
        if (mesh.triangles.empty()) continue;
        positions += mesh.positions.size();
        indices += mesh.triangles.size();
        largest = std::max(largest, mesh.positions.size());
    }
    out.indices.reserve(indices);
    SharedVertices shared(out.vertices, std::min(positions, indices));
    constexpr std::uint32_t kUnset = 0xFFFFFFFFu;
    std::vector<std::uint32_t> remap(largest, kUnset);
    std::vector<Vec3d> moved(largest);
    std::vector<bool> done(largest, false);
    std::vector<std::uint32_t> touched;
    std::uint32_t face = 0;  // the file's triangle number (check_raw: fewer than 2^24)
    for (const RawInstance& use : model.instances) {
        const RawMesh& mesh = model.meshes[use.mesh];
        if (mesh.triangles.empty()) continue;
        const Matrix4d m = multiply(user, use.transform);
        auto position = [&](std::uint32_t v) -> const Vec3d& {
            if (!done[v]) {
                moved[v] = transform_point(m, mesh.positions[v]);
                if (!finite3(moved[v]))
                    throw ModelError(mesh_prefix(model, use.mesh) + "vertex " + std::to_string(v) +
                                     " is not finite after the transform: " + vec_str(moved[v]));
                done[v] = true;
                touched.push_back(v);
            }
            return moved[v];
        };
        for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3, ++face) {
            const std::uint32_t* tri = &mesh.triangles[t];
            const Vec3d& a = position(tri[0]);
            const Vec3d& b = position(tri[1]);
            const Vec3d& c = position(tri[2]);
            const Vec3d n = cross(b - a, c - a);
            if (n.x == 0 && n.y == 0 && n.z == 0) {
                // From the first drop on, each kept triangle records its file number
                // (those kept before it are numbered as they stand).
                if (out.faces.empty()) {
                    out.faces.resize(out.indices.size() / 3);
                    std::iota(out.faces.begin(), out.faces.end(), std::uint32_t(0));
                }
                ++out.dropped_degenerate;
                continue;
            }
            if (out.dropped_degenerate) out.faces.push_back(face);
            for (unsigned k = 0; k < 3; ++k) {
                const std::uint32_t v = tri[k];
                if (remap[v] == kUnset) remap[v] = shared.index_of(moved[v]);
                out.indices.push_back(remap[v]);
            }
        }
        for (const std::uint32_t v : touched) {
            done[v] = false;
            remap[v] = kUnset;
        }
        touched.clear();
    }
    if (out.indices.empty())
        throw ModelError("no triangles (all " + std::to_string(out.dropped_degenerate) + " have zero area)");
    return out;
}

}  // namespace octray::model_formats
