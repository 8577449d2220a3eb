// io/model_loader.cpp — see model_loader.hpp.
//
// How a file is read (assimp 5.2, Debian's libassimp):
// 1. The extension picks the format. .obj and .ply each have one assimp reader, which
//    assimp uses directly. .gltf/.glb are claimed by two readers (glTF 1 and 2); when
//    neither accepts a file, assimp would try every reader it has on the file's bytes (a
//    text file called .glb can then be read as something else), so the glTF 2 reader is
//    asked first and a file it does not accept is refused unread.
// 2. Importer::ReadFile with no post-processing; the reader that read it must be the one
//    the extension names. Every file assimp opens goes through LimitedIOSystem, which
//    refuses files over kMaxModelFileBytes.
// 3. This file checks assimp's raw data before any post-processing step touches it
//    (those steps index vertex arrays with the file's indices and do not check them):
//    every index in range, every vertex of a mesh with polygons finite (before
//    JoinIdenticalVertices-like steps could merge a NaN away: none is used), the
//    triangle count within kMaxModelTriangles, at least one triangle.
// 4. ValidateDataStructure, then Triangulate | SortByPType.
// Guards around assimp 5.2 bugs found by fuzzing (cut and corrupted copies of small
// models): a PLY file must have an "end_header" line (check_ply_header_end), and a
// reader that keeps reading at the end of a file is stopped (GuardedStream).
// 5. The node graph is walked here, in double: each mesh once per node that uses it,
//    under the node's global transform and then the user's; only 3-index faces are taken
//    (points and lines are left out); vertices are shared by exact position; zero-area
//    triangles are dropped and counted.
//
// Logging: assimp logs through one process-wide DefaultLogger. If no logger is set, a
// silent one is installed, which records warnings for the thread that is loading: the glTF
// 2 reader drops faces with out-of-range indices with only a warning, and that warning
// is turned into an error here. A logger set by a host program is left alone.
#include "model_loader.hpp"

#include "model_math.hpp"

#include <assimp/DefaultIOSystem.h>
#include <assimp/IOStream.hpp>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/importerdesc.h>
#include <assimp/BaseImporter.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <unordered_map>

namespace octray {

using namespace model_math;

// ---- assimp plumbing ----------------------------------------------------------------

namespace {

thread_local std::vector<std::string>* t_warnings = nullptr;

// Silent; keeps warnings and errors for the thread that set t_warnings.
class QuietLogger final : public Assimp::Logger {
public:
    QuietLogger() : Assimp::Logger(Assimp::Logger::NORMAL) {}
    bool attachStream(Assimp::LogStream*, unsigned int) override { return false; }
    bool detachStream(Assimp::LogStream*, unsigned int) override { return false; }

private:
    void OnVerboseDebug(const char*) override {}
    void OnDebug(const char*) override {}
    void OnInfo(const char*) override {}
    void OnWarn(const char* m) override { keep(m); }
    void OnError(const char* m) override { keep(m); }
    static void keep(const char* m) {
        if (t_warnings) t_warnings->emplace_back(m);
    }
};

void quiet_assimp_logging() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (Assimp::DefaultLogger::isNullLogger()) Assimp::DefaultLogger::set(new QuietLogger);
    });
}

// Records the warnings assimp logs on this thread while it is alive.
class WarningCapture {
public:
    WarningCapture() : previous_(t_warnings) { t_warnings = &warnings; }
    ~WarningCapture() { t_warnings = previous_; }
    WarningCapture(const WarningCapture&) = delete;
    WarningCapture& operator=(const WarningCapture&) = delete;
    std::vector<std::string> warnings;

private:
    std::vector<std::string>* previous_;
};

// A file as assimp reads it, with a guard: assimp 5.2's PLY reader loops for ever at the
// end of a file whose header is cut short (it reads nothing, again and again). A reader
// that keeps reading at the end of the file is stopped with an exception, which assimp
// turns into a failed import.
class GuardedStream final : public Assimp::IOStream {
public:
    explicit GuardedStream(Assimp::IOStream* inner) : inner_(inner) {}
    ~GuardedStream() override { delete inner_; }
    std::size_t Read(void* buffer, std::size_t size, std::size_t count) override {
        const std::size_t n = inner_->Read(buffer, size, count);
        if (n == 0 && size > 0 && count > 0 && ++empty_reads_ > kMaxEmptyReads)
            throw std::runtime_error("unexpected end of file (assimp's reader kept reading past it)");
        return n;
    }
    std::size_t Write(const void* buffer, std::size_t size, std::size_t count) override {
        return inner_->Write(buffer, size, count);
    }
    aiReturn Seek(std::size_t offset, aiOrigin origin) override { return inner_->Seek(offset, origin); }
    std::size_t Tell() const override { return inner_->Tell(); }
    std::size_t FileSize() const override { return inner_->FileSize(); }
    void Flush() override { inner_->Flush(); }

private:
    static constexpr int kMaxEmptyReads = 256;
    Assimp::IOStream* inner_;
    int empty_reads_ = 0;
};

// assimp's file access: a size limit on every file it opens, and GuardedStream.
class LimitedIOSystem final : public Assimp::DefaultIOSystem {
public:
    Assimp::IOStream* Open(const char* file, const char* mode) override {
        std::error_code ec;
        const std::uintmax_t size = std::filesystem::file_size(file, ec);
        if (!ec && size > kMaxModelFileBytes) {
            if (refused.empty())
                refused = "file too large: " + std::string(file) + " is " + std::to_string(size) + " bytes (limit " +
                          std::to_string(kMaxModelFileBytes) + ")";
            return nullptr;
        }
        Assimp::IOStream* inner = Assimp::DefaultIOSystem::Open(file, mode);
        return inner ? new GuardedStream(inner) : nullptr;
    }
    std::string refused;  // why the first refused file was refused
};

struct Format {
    const char* extension;
    const char* reader;  // aiImporterDesc::mName of the assimp reader that must read it
    const char* name;    // MeshData::format
};
constexpr Format kFormats[] = {
    {".gltf", "glTF2 Importer", "glTF 2.0"},
    {".glb", "glTF2 Importer", "glTF 2.0"},
    {".obj", "Wavefront Object Importer", "Wavefront OBJ"},
    {".ply", "Stanford Polygon Library (PLY) Importer", "PLY"},
};
constexpr const char* kGltf1Reader = "glTF Importer";

int reader_index(const Assimp::Importer& imp, const char* name) {
    for (std::size_t i = 0; i < imp.GetImporterCount(); ++i) {
        const aiImporterDesc* d = imp.GetImporterInfo(i);
        if (d && std::strcmp(d->mName, name) == 0) return static_cast<int>(i);
    }
    return -1;
}

[[noreturn]] void unreadable(const std::string& why) {
    throw ModelError("unsupported or unreadable model file: " + why);
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

// The file exists, is a readable regular file and is not too large.
void check_file(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw ModelError(std::string("cannot open: ") + std::strerror(errno));
    std::fclose(f);
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw ModelError(std::string("cannot open: ") + std::strerror(EISDIR));
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw ModelError("cannot open: " + ec.message());
    if (size > kMaxModelFileBytes)
        throw ModelError("file too large: " + std::to_string(size) + " bytes (limit " +
                         std::to_string(kMaxModelFileBytes) + ")");
}

// assimp 5.2's PLY reader runs past the end of its buffer when the header has no
// "end_header" line (a cut or corrupted header): it is not given such a file. Only this
// one line is looked for, as a format's magic number is, in the first kPlyHeaderScan bytes;
// the header itself is assimp's to read.
constexpr std::size_t kPlyHeaderScan = 1 << 16;

void check_ply_header_end(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw ModelError(std::string("cannot open: ") + std::strerror(errno));
    std::string head(kPlyHeaderScan, '\0');
    head.resize(std::fread(&head[0], 1, head.size(), f));
    std::fclose(f);
    for (std::size_t at = head.find("\nend_header"); at != std::string::npos; at = head.find("\nend_header", at + 1)) {
        const std::size_t after = at + 11;
        if (after < head.size() && (head[after] == '\n' || (head[after] == '\r' && after + 1 < head.size() &&
                                                              head[after + 1] == '\n')))
            return;
    }
    unreadable("the PLY header has no end_header line in its first " + std::to_string(kPlyHeaderScan) + " bytes");
}

Matrix4d to_double(const aiMatrix4x4& m) {
    return {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4};
}

Vec3d transform_point(const Matrix4d& m, const Vec3d& p) {
    return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
            m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

Vec3d to_vec(const aiVector3D& v) { return {double(v.x), double(v.y), double(v.z)}; }

// "mesh 2 'wheel': " where the file has several meshes, else "".
std::string mesh_prefix(const aiScene& scene, unsigned m) {
    if (scene.mNumMeshes <= 1) return "";
    std::string p = "mesh " + std::to_string(m);
    if (scene.mMeshes[m]->mName.length > 0) p += " '" + std::string(scene.mMeshes[m]->mName.C_Str()) + "'";
    return p + ": ";
}

// Calls visit(node, global transform) for every node, parents first; no recursion, and a
// bound on the number of nodes visited (assimp's graph is a tree, but a broken one must
// not loop).
template <class Visit>
void walk_nodes(const aiScene& scene, Visit visit) {
    if (!scene.mRootNode) return;
    std::vector<std::pair<const aiNode*, Matrix4d>> stack{{scene.mRootNode, to_double(scene.mRootNode->mTransformation)}};
    std::size_t visited = 0;
    while (!stack.empty()) {
        auto [node, global] = stack.back();
        stack.pop_back();
        if (++visited > (std::size_t(1) << 24)) unreadable("node graph too large or cyclic");
        visit(*node, global);
        if (node->mNumChildren > 0 && !node->mChildren) unreadable("node without its children");
        for (unsigned c = node->mNumChildren; c-- > 0;) {
            const aiNode* child = node->mChildren[c];
            if (!child) unreadable("null child node");
            stack.emplace_back(child, multiply(global, to_double(child->mTransformation)));
        }
    }
}

// Step 3 of the file comment: assimp's raw data, before any post-processing.
void check_raw_scene(const aiScene& scene) {
    if (scene.mNumMeshes > 0 && !scene.mMeshes) unreadable("meshes missing");
    std::vector<std::uint64_t> triangles(scene.mNumMeshes, 0);  // after triangulation, per use
    for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
        const aiMesh* mesh = scene.mMeshes[m];
        if (!mesh) unreadable("null mesh");
        if (mesh->mNumVertices > 0 && !mesh->mVertices) unreadable(mesh_prefix(scene, m) + "no vertex positions");
        if (mesh->mNumFaces > 0 && !mesh->mFaces) unreadable(mesh_prefix(scene, m) + "faces missing");
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices > 0 && !face.mIndices) unreadable(mesh_prefix(scene, m) + "face without indices");
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= mesh->mNumVertices)
                    throw ModelError(mesh_prefix(scene, m) + "index " + std::to_string(face.mIndices[k]) +
                                     " out of range (" + std::to_string(mesh->mNumVertices) + " vertices)");
            if (face.mNumIndices >= 3) triangles[m] += face.mNumIndices - 2;
        }
        for (unsigned b = 0; b < mesh->mNumBones; ++b) {  // SortByPType remaps bone weights
            const aiBone* bone = mesh->mBones ? mesh->mBones[b] : nullptr;
            if (!bone || (bone->mNumWeights > 0 && !bone->mWeights)) unreadable(mesh_prefix(scene, m) + "broken bone");
            for (unsigned w = 0; w < bone->mNumWeights; ++w)
                if (bone->mWeights[w].mVertexId >= mesh->mNumVertices)
                    unreadable(mesh_prefix(scene, m) + "bone weight of vertex " +
                               std::to_string(bone->mWeights[w].mVertexId) + " out of range");
        }
        if (triangles[m] == 0) continue;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v)
            if (!finite3(to_vec(mesh->mVertices[v])))
                throw ModelError(mesh_prefix(scene, m) + "vertex " + std::to_string(v) +
                                 " is not finite: " + vec_str(to_vec(mesh->mVertices[v])));
    }
    std::uint64_t total = 0;
    walk_nodes(scene, [&](const aiNode& node, const Matrix4d&) {
        if (node.mNumMeshes > 0 && !node.mMeshes) unreadable("node without its meshes");
        for (unsigned i = 0; i < node.mNumMeshes; ++i) {
            if (node.mMeshes[i] >= scene.mNumMeshes) unreadable("node uses mesh " + std::to_string(node.mMeshes[i]) +
                                                                " of " + std::to_string(scene.mNumMeshes));
            total += triangles[node.mMeshes[i]];
            if (total > kMaxModelTriangles)
                throw ModelError("too many triangles: more than " + std::to_string(kMaxModelTriangles) + " (the limit)");
        }
    });
    if (total == 0) throw ModelError("no triangles");
}

struct PositionKey {
    std::uint64_t x, y, z;
    bool operator==(const PositionKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct PositionKeyHash {
    std::size_t operator()(const PositionKey& k) const {
        std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2)) * 0xC2B2AE3D27D4EB4Full;
        h ^= (k.z + 0x165667B19E3779F9ull + (h << 6) + (h >> 2)) * 0x9E3779B97F4A7C15ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
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

// Step 5 of the file comment.
void collect_triangles(const aiScene& scene, const Matrix4d& user, MeshData& out) {
    std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> shared;
    constexpr std::uint32_t kUnset = 0xFFFFFFFFu;
    walk_nodes(scene, [&](const aiNode& node, const Matrix4d& global) {
        const Matrix4d m = multiply(user, global);
        for (unsigned i = 0; i < node.mNumMeshes; ++i) {
            const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
            std::vector<std::uint32_t> remap(mesh.mNumVertices, kUnset);
            std::vector<Vec3d> moved(mesh.mNumVertices);
            std::vector<bool> done(mesh.mNumVertices, false);
            auto position = [&](unsigned v) -> const Vec3d& {
                if (!done[v]) {
                    moved[v] = transform_point(m, to_vec(mesh.mVertices[v]));
                    if (!finite3(moved[v]))
                        throw ModelError("vertex " + std::to_string(v) + " is not finite after the transform: " +
                                         vec_str(moved[v]));
                    done[v] = true;
                }
                return moved[v];
            };
            for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
                const aiFace& face = mesh.mFaces[f];
                if (face.mNumIndices != 3) continue;  // points and lines
                const Vec3d& a = position(face.mIndices[0]);
                const Vec3d& b = position(face.mIndices[1]);
                const Vec3d& c = position(face.mIndices[2]);
                const Vec3d n = cross(b - a, c - a);
                if (n.x == 0 && n.y == 0 && n.z == 0) {
                    ++out.dropped_degenerate;
                    continue;
                }
                for (unsigned k = 0; k < 3; ++k) {
                    const unsigned v = face.mIndices[k];
                    if (remap[v] == kUnset) {
                        const auto [it, added] =
                            shared.emplace(key_of(moved[v]), static_cast<std::uint32_t>(out.vertices.size()));
                        if (added) out.vertices.push_back(moved[v]);
                        remap[v] = it->second;
                    }
                    out.indices.push_back(remap[v]);
                }
            }
        }
    });
}

}  // namespace

MeshData load_model(const std::string& path, const MeshTransform& transform) {
    if (const std::string p = transform.problem(); !p.empty()) throw ModelError("transform: " + p);
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    const Format* format = nullptr;
    for (const Format& f : kFormats)
        if (ext == f.extension) format = &f;
    if (!format)
        throw ModelError("unknown model format '" + ext + "' (expected .gltf, .glb, .obj or .ply)");
    check_file(path);
    quiet_assimp_logging();

    try {
        Assimp::Importer imp;
        auto* io = new LimitedIOSystem;
        imp.SetIOHandler(io);  // the importer owns it
        const int reader = reader_index(imp, format->reader);
        if (reader < 0) throw ModelError(std::string("this assimp has no reader for ") + format->name);

        if (ext == ".gltf" || ext == ".glb") {  // step 1 of the file comment
            if (!imp.GetImporter(reader)->CanRead(path, io, true)) {
                const int v1 = reader_index(imp, kGltf1Reader);
                if (v1 >= 0 && imp.GetImporter(v1)->CanRead(path, io, true))
                    throw ModelError("glTF 1.0 is not supported (glTF 2.0 only)");
                if (!io->refused.empty()) throw ModelError(io->refused);
                unreadable("not a glTF 2.0 file");
            }
        }

        if (ext == ".ply") check_ply_header_end(path);

        WarningCapture capture;
        const aiScene* scene = imp.ReadFile(path, 0);
        if (!io->refused.empty()) throw ModelError(io->refused);
        if (!scene) unreadable(imp.GetErrorString());
        const int used = imp.GetPropertyInteger("importerIndex", -1);
        if (used != reader) {
            const aiImporterDesc* d = used >= 0 ? imp.GetImporterInfo(used) : nullptr;
            unreadable(std::string("read as ") + (d ? d->mName : "an unknown format") + ", not " + format->name);
        }
        for (const std::string& w : capture.warnings)
            if (lower(w).find("out-of-range ind") != std::string::npos)
                throw ModelError("index out of range in some faces (assimp's reader: " + w + ")");

        check_raw_scene(*scene);
        if (!(scene = imp.ApplyPostProcessing(aiProcess_ValidateDataStructure))) unreadable(imp.GetErrorString());
        if (!(scene = imp.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_SortByPType)))
            unreadable(imp.GetErrorString());

        MeshData out;
        out.format = format->name;
        collect_triangles(*scene, transform.to_matrix(), out);
        if (out.indices.empty())
            throw ModelError("no triangles (all " + std::to_string(out.dropped_degenerate) + " have zero area)");
        return out;
    } catch (const ModelError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw ModelError("out of memory reading the model");
    } catch (const std::exception& e) {
        unreadable(e.what());
    }
}

}  // namespace octray
