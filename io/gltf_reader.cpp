// io/gltf_reader.cpp — read_gltf (model_formats.hpp): glTF 2.0 (.gltf JSON and .glb
// binary) through tinygltf, compiled here so the sanitizer and fuzz builds see into it.
//
// Format: Khronos, "glTF 2.0 Specification" (accessors §3.6, meshes §3.7, nodes §3.5).
// Library: Debian's libtinygltf-dev (header-only; its JSON parser is nlohmann/json).
//
// tinygltf parses the JSON and loads buffers; io/gltf_accessors.cpp reads positions and
// indices out of those buffers itself, checking every accessor's range against its buffer
// view and buffer before a single element is copied. What is refused, and why:
// - JSON nested deeper than kMaxJsonDepth: tinygltf converts "extras" recursively, so a
//   deep nest would exhaust the stack; no glTF file needs more than a dozen levels.
// - an external buffer or image URI that is absolute or leaves the model's folder
//   ("../../etc/passwd"), or names a file larger than kMaxModelFileBytes: files are opened
//   through FsCallbacks that only see the model's folder. Images are never decoded.
// - a buffer whose byteLength differs from its data (tinygltf's check), so a data URI can
//   never decode to more than its own text: memory stays bounded by the input.
// - an accessor whose count·stride runs past its view, and a view that runs past its
//   buffer: "accessor 3: 2000000000 elements of 12 bytes run past buffer view 0 (12 bytes)".
// - a node reached twice (glTF nodes form trees; a DAG would multiply instances).
// Positions must be VEC3 FLOAT and indices unsigned byte, short or int (the spec's rule);
// sparse accessors are applied. Modes: triangles, strips and fans; points and lines are
// left out. Each primitive is one RawMesh; each node that uses its mesh, one instance.

// tinygltf's definitions are compiled here, once; gltf_accessors.hpp includes it too.
#define TINYGLTF_IMPLEMENTATION
#include "gltf_accessors.hpp"
#include "model_math.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <set>
#include <system_error>

namespace octray::model_formats {

using namespace model_math;
using namespace gltf;

namespace {

constexpr int kMaxJsonDepth = 64;

// Required extensions that change how positions or indices are stored: a file that needs
// one cannot be read without it. Others (materials, lights, texture transforms) do not
// touch geometry and are ignored.
const std::set<std::string> kGeometryExtensions = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                                   "KHR_mesh_quantization"};

// The first line of tinygltf's message, without its trailing full stop, cut at 200
// characters (a message may quote a URI of any length).
std::string first_line(const std::string& s) {
    std::string line = s.substr(0, std::min(s.find('\n'), std::size_t(200)));
    while (!line.empty() && (line.back() == '.' || line.back() == ' ' || line.back() == '\r')) line.pop_back();
    return line.empty() ? std::string("tinygltf refused it") : line;
}

// The JSON part of the input: the whole of a .gltf, the first chunk of a .glb (its
// header is checked again by tinygltf; here only as far as finding the chunk).
std::string_view json_part(std::string_view bytes, bool binary) {
    if (!binary) return bytes;
    if (bytes.size() < 20 || bytes.substr(0, 4) != "glTF") unreadable("not a binary glTF file (no 'glTF' magic)");
    std::uint32_t version = 0, chunk_length = 0, chunk_type = 0;
    std::memcpy(&version, bytes.data() + 4, 4);
    std::memcpy(&chunk_length, bytes.data() + 12, 4);
    std::memcpy(&chunk_type, bytes.data() + 16, 4);
    if (version != 2) throw ModelError("glTF " + std::to_string(version) + ".0 binary is not supported (glTF 2.0 only)");
    if (chunk_type != 0x4E4F534Au) unreadable("the first chunk of the .glb is not JSON");
    if (chunk_length > bytes.size() - 20) unreadable("the JSON chunk runs past the end of the file");
    return bytes.substr(20, chunk_length);
}

// ---- file access: the model's folder only ---------------------------------------------

struct Folder {
    std::filesystem::path base;  // weakly canonical
};

// The file `path` names, if it lies inside the model's folder; else empty.
std::filesystem::path inside(const Folder& folder, const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::path(path), ec);
    if (ec) return {};
    const auto rel = p.lexically_relative(folder.base);
    if (rel.empty() || rel.is_absolute() || *rel.begin() == "..") return {};
    return p;
}

// "%2e%2e/x" as tinygltf reads it: "../x".
std::string percent_decoded(const std::string& uri) {
    auto hex = [](char c) {
        return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
    };
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// A buffer's data URI holds exactly its byteLength (checked here so the message need not
// quote the URI, which tinygltf's does); what it decodes to is at most 3/4 of its text.
void check_data_uri(const std::string& uri, const nlohmann::json& buffer, std::size_t b) {
    const std::size_t comma = uri.find(',');
    if (comma == std::string::npos || uri.rfind(";base64", comma) == std::string::npos)
        unreadable("buffers[" + std::to_string(b) + "]: a data URI that is not base64");
    const std::size_t text = uri.size() - comma - 1;
    std::size_t padding = 0;
    for (std::size_t i = uri.size(); i > comma + 1 && uri[i - 1] == '=' && padding < 2; --i) ++padding;
    const std::size_t holds = text / 4 * 3 - (text % 4 == 0 ? padding : 0);
    const auto length = buffer.find("byteLength");
    if (length != buffer.end() && length->is_number_unsigned() && length->get<std::uint64_t>() != holds)
        unreadable("buffers[" + std::to_string(b) + "]: byteLength " + std::to_string(length->get<std::uint64_t>()) +
                   " but its data URI holds " + std::to_string(holds) + " bytes");
}

// Parses the JSON once before tinygltf does: depth bounded, the version checked (a glTF
// 1.0 file gets its own message rather than tinygltf's first complaint about it), and
// every external buffer URI inside the model's folder, named when it is not.
void check_json(std::string_view json, const Folder& folder) {
    nlohmann::json doc;
    try {
        doc = nlohmann::json::parse(
            json.begin(), json.end(),
            [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
                if (depth > kMaxJsonDepth)
                    unreadable("JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
                return true;
            });
    } catch (const nlohmann::json::exception& e) {
        unreadable(std::string("JSON: ") + e.what());
    }
    if (!doc.is_object()) unreadable("the JSON is not an object");
    const auto asset = doc.find("asset");
    if (asset == doc.end() || !asset->is_object()) unreadable("no \"asset\" object (glTF 2.0 requires one)");
    const auto version = asset->find("version");
    if (version == asset->end() || !version->is_string()) unreadable("no asset.version (glTF 2.0 requires one)");
    const std::string v = version->get<std::string>();
    if (v.rfind("2.", 0) != 0) throw ModelError("glTF " + v + " is not supported (glTF 2.0 only)");
    if (const auto required = doc.find("extensionsRequired"); required != doc.end() && required->is_array())
        for (const nlohmann::json& name : *required)
            if (name.is_string() && kGeometryExtensions.count(name.get<std::string>()))
                throw ModelError("glTF extension " + name.get<std::string>() + " is not supported (it encodes the geometry)");
    const auto buffers = doc.find("buffers");
    if (buffers == doc.end() || !buffers->is_array()) return;
    for (std::size_t b = 0; b < buffers->size(); ++b) {
        const nlohmann::json& buffer = (*buffers)[b];
        if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string()) continue;
        const std::string uri = buffer["uri"].get<std::string>();
        if (uri.rfind("data:", 0) == 0) {
            check_data_uri(uri, buffer, b);
            continue;
        }
        const std::string path = percent_decoded(uri);
        const std::filesystem::path file = inside(folder, (folder.base / path).string());
        if (std::filesystem::path(path).is_absolute() || file.empty())
            throw ModelError("buffers[" + std::to_string(b) + "].uri '" + uri + "' is outside the model's folder");
        std::error_code ec;
        const std::uintmax_t size = std::filesystem::file_size(file, ec);
        if (!ec && size > kMaxModelFileBytes)
            throw ModelError("file too large: " + path + " is " + std::to_string(size) + " bytes (limit " +
                             std::to_string(kMaxModelFileBytes) + ")");
    }
}

bool file_exists(const std::string& path, void* user) {
    const std::filesystem::path p = inside(*static_cast<Folder*>(user), path);
    std::error_code ec;
    return !p.empty() && std::filesystem::is_regular_file(p, ec);
}

std::string expand_path(const std::string& path, void*) { return path; }

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    const std::filesystem::path p = inside(*static_cast<Folder*>(user), path);
    if (p.empty()) {
        if (err) *err += "outside the model's folder";
        return false;
    }
    std::error_code ec;
    const std::uintmax_t size = std::filesystem::file_size(p, ec);
    if (ec || size > kMaxModelFileBytes) {
        if (err) *err += ec ? ec.message() : "larger than " + std::to_string(kMaxModelFileBytes) + " bytes";
        return false;
    }
    std::ifstream in(p, std::ios::binary);
    out->resize(static_cast<std::size_t>(size));
    if (size > 0) in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size));
    if (!in) {
        if (err) *err += "cannot read";
        return false;
    }
    return true;
}

bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not allowed";
    return false;
}

// Images are not needed for geometry: accepted unread.
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                void*) {
    return true;
}


// ---- nodes ----------------------------------------------------------------------------

// A glTF matrix (column-major) or TRS as a row-major Matrix4d; sizes checked.
Matrix4d local_matrix(const tinygltf::Node& node, std::size_t index) {
    const std::string what = "node " + std::to_string(index);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) unreadable(what + ": matrix must have 16 numbers");
        Matrix4d m{};
        for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 4; ++c) m[4 * r + c] = node.matrix[std::size_t(4 * c + r)];
        return m;
    }
    if (!node.translation.empty() && node.translation.size() != 3) unreadable(what + ": translation must have 3 numbers");
    if (!node.scale.empty() && node.scale.size() != 3) unreadable(what + ": scale must have 3 numbers");
    if (!node.rotation.empty() && node.rotation.size() != 4) unreadable(what + ": rotation must have 4 numbers");
    const double tx = node.translation.empty() ? 0 : node.translation[0];
    const double ty = node.translation.empty() ? 0 : node.translation[1];
    const double tz = node.translation.empty() ? 0 : node.translation[2];
    const double sx = node.scale.empty() ? 1 : node.scale[0];
    const double sy = node.scale.empty() ? 1 : node.scale[1];
    const double sz = node.scale.empty() ? 1 : node.scale[2];
    double x = 0, y = 0, z = 0, w = 1;  // unit quaternion (x, y, z, w)
    if (!node.rotation.empty()) {
        x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
        const double len = std::sqrt(x * x + y * y + z * z + w * w);
        if (!(len > 0) || !std::isfinite(len)) unreadable(what + ": rotation is not a quaternion");
        x /= len, y /= len, z /= len, w /= len;
    }
    // T · R · S
    const double r00 = 1 - 2 * (y * y + z * z), r01 = 2 * (x * y - z * w), r02 = 2 * (x * z + y * w);
    const double r10 = 2 * (x * y + z * w), r11 = 1 - 2 * (x * x + z * z), r12 = 2 * (y * z - x * w);
    const double r20 = 2 * (x * z - y * w), r21 = 2 * (y * z + x * w), r22 = 1 - 2 * (x * x + y * y);
    return {r00 * sx, r01 * sy, r02 * sz, tx, r10 * sx, r11 * sy, r12 * sz, ty,
            r20 * sx, r21 * sy, r22 * sz, tz, 0,        0,        0,        1};
}

}  // namespace

RawModel read_gltf(std::string_view bytes, bool binary, const std::filesystem::path& base_dir) {
    try {
        Folder folder;
        std::error_code ec;
        folder.base = std::filesystem::weakly_canonical(base_dir.empty() ? std::filesystem::path(".") : base_dir, ec);
        if (ec) throw ModelError("cannot resolve the model's folder: " + ec.message());
        check_json(json_part(bytes, binary), folder);

        tinygltf::TinyGLTF loader;
        loader.SetFsCallbacks(tinygltf::FsCallbacks{&file_exists, &expand_path, &read_whole_file, &write_whole_file,
                                                    &folder});
        loader.SetImageLoader(&skip_image, nullptr);
        tinygltf::Model model;
        std::string err, warn;
        const std::string base = folder.base.string();
        if (bytes.size() > 0xFFFFFFFFu) throw ModelError("file too large for glTF");
        const unsigned size = static_cast<unsigned>(bytes.size());
        const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                                             reinterpret_cast<const unsigned char*>(bytes.data()),
                                                             size, base)
                               : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, base);
        if (!ok) unreadable(first_line(err));

        RawModel out;
        // Each (mesh, primitive) with triangles becomes a RawMesh; first[m] is mesh m's first.
        std::vector<std::size_t> first(model.meshes.size() + 1, 0);
        for (std::size_t m = 0; m < model.meshes.size(); ++m) {
            first[m] = out.meshes.size();
            const tinygltf::Mesh& mesh = model.meshes[m];
            for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
                const tinygltf::Primitive& prim = mesh.primitives[p];
                if (!has_triangles(prim.mode)) continue;
                const auto pos = prim.attributes.find("POSITION");
                if (pos == prim.attributes.end()) continue;  // nothing to place
                RawMesh raw;
                raw.name = mesh.name.empty() ? "mesh " + std::to_string(m) : mesh.name;
                if (mesh.primitives.size() > 1) raw.name += " primitive " + std::to_string(p);
                raw.positions = read_positions(model, pos->second);
                const std::vector<std::uint32_t> order = read_indices(model, prim, raw.positions.size());
                triangulate(order, prim.mode, raw, "mesh " + std::to_string(m) + " primitive " + std::to_string(p));
                out.meshes.push_back(std::move(raw));
            }
        }
        first[model.meshes.size()] = out.meshes.size();

        // The scene's node trees, parents first; each node at most once.
        std::vector<int> roots;
        if (!model.scenes.empty()) {
            const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
            if (static_cast<std::size_t>(s) >= model.scenes.size())
                unreadable("default scene " + std::to_string(s) + " does not exist");
            roots = model.scenes[static_cast<std::size_t>(s)].nodes;
        } else {
            // No scene: every node that is nobody's child is a root.
            std::vector<bool> child(model.nodes.size(), false);
            for (const tinygltf::Node& n : model.nodes)
                for (const int c : n.children)
                    if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[static_cast<std::size_t>(c)] = true;
            for (std::size_t n = 0; n < model.nodes.size(); ++n)
                if (!child[n]) roots.push_back(static_cast<int>(n));
        }
        std::vector<bool> seen(model.nodes.size(), false);
        const Matrix4d identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        std::vector<std::pair<int, Matrix4d>> stack;
        for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, identity);
        while (!stack.empty()) {
            const auto [index, parent] = stack.back();
            stack.pop_back();
            if (index < 0 || static_cast<std::size_t>(index) >= model.nodes.size())
                unreadable("node " + std::to_string(index) + " does not exist");
            const std::size_t n = static_cast<std::size_t>(index);
            if (seen[n]) unreadable("node " + std::to_string(n) + " is reached twice (glTF nodes form trees)");
            seen[n] = true;
            const tinygltf::Node& node = model.nodes[n];
            const Matrix4d global = multiply(parent, local_matrix(node, n));
            if (node.mesh >= 0) {
                if (static_cast<std::size_t>(node.mesh) >= model.meshes.size())
                    unreadable("node " + std::to_string(n) + ": mesh " + std::to_string(node.mesh) +
                               " does not exist");
                const std::size_t m = static_cast<std::size_t>(node.mesh);
                for (std::size_t r = first[m]; r < first[m + 1]; ++r)
                    out.instances.push_back(RawInstance{static_cast<std::uint32_t>(r), global});
            }
            for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.emplace_back(*c, global);
        }
        return out;
    } catch (...) {
        rethrow_as_model_error("glTF");
    }
}

}  // namespace octray::model_formats
