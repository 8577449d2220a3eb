// io/gltf_reader.cpp — read_gltf (model_formats.hpp): glTF 2.0 (.gltf JSON and .glb
// binary) through tinygltf, compiled here so the sanitizer and fuzz builds see into it.
//
// Format: Khronos, "glTF 2.0 Specification" (accessors §3.6, meshes §3.7, nodes §3.5).
// Library: Debian's libtinygltf-dev (header-only; its JSON parser is nlohmann/json).
//
// tinygltf parses the JSON and loads buffers; this file reads positions and indices out
// of those buffers itself, checking every accessor's range against its buffer view and
// buffer before a single element is copied. What is refused, and why:
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
#include "model_formats.hpp"

#include "model_math.hpp"

#include <nlohmann/json.hpp>

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#define TINYGLTF_NO_INCLUDE_JSON
#include <tiny_gltf.h>  // a system header (CMake): its own warnings are not ours

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <new>
#include <set>
#include <system_error>

namespace octray::model_formats {

using namespace model_math;

namespace {

constexpr int kMaxJsonDepth = 64;

// Required extensions that change how positions or indices are stored: a file that needs
// one cannot be read without it. Others (materials, lights, texture transforms) do not
// touch geometry and are ignored.
const std::set<std::string> kGeometryExtensions = {"KHR_draco_mesh_compression", "EXT_meshopt_compression",
                                                   "KHR_mesh_quantization"};

[[noreturn]] void unreadable(const std::string& why) { throw ModelError("unreadable glTF: " + why); }

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

// ---- accessors ------------------------------------------------------------------------

struct View {
    const unsigned char* data = nullptr;
    std::size_t count = 0;
    std::size_t stride = 0;
    std::size_t element = 0;
};

std::size_t component_bytes(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
        default: return 0;
    }
}

// count elements of `element` bytes, `stride` apart, from byte `offset` of buffer view
// `view_index`: checked against the view and the view against its buffer.
View view_of(const tinygltf::Model& model, const std::string& what, int view_index, std::size_t offset,
             std::size_t count, std::size_t element, std::size_t min_stride) {
    if (view_index < 0 || static_cast<std::size_t>(view_index) >= model.bufferViews.size())
        unreadable(what + ": buffer view " + std::to_string(view_index) + " does not exist");
    const tinygltf::BufferView& bv = model.bufferViews[static_cast<std::size_t>(view_index)];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= model.buffers.size())
        unreadable("buffer view " + std::to_string(view_index) + ": buffer " + std::to_string(bv.buffer) +
                   " does not exist");
    const std::vector<unsigned char>& data = model.buffers[static_cast<std::size_t>(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        unreadable("buffer view " + std::to_string(view_index) + " (" + std::to_string(bv.byteLength) +
                   " bytes from " + std::to_string(bv.byteOffset) + ") runs past buffer " +
                   std::to_string(bv.buffer) + " (" + std::to_string(data.size()) + " bytes)");
    const std::size_t stride = bv.byteStride ? bv.byteStride : min_stride;
    if (stride < min_stride)
        unreadable(what + ": byte stride " + std::to_string(stride) + " is less than an element's " +
                   std::to_string(min_stride) + " bytes");
    View v{nullptr, count, stride, element};
    if (count == 0) return v;
    // offset + stride·(count − 1) + element <= byteLength, without overflow.
    const std::size_t room = bv.byteLength;
    const bool fits = offset <= room && element <= room - offset &&
                      (count - 1) <= (room - offset - element) / stride;
    if (!fits)
        unreadable(what + ": " + std::to_string(count) + " elements of " + std::to_string(element) +
                   " bytes run past buffer view " + std::to_string(view_index) + " (" + std::to_string(room) +
                   " bytes)");
    v.data = data.data() + bv.byteOffset + offset;
    return v;
}

const tinygltf::Accessor& accessor_at(const tinygltf::Model& model, int index, const std::string& what) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size())
        unreadable(what + ": accessor " + std::to_string(index) + " does not exist");
    return model.accessors[static_cast<std::size_t>(index)];
}

std::uint32_t read_index(const unsigned char* p, int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        default: {
            std::uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

void check_index_type(int type, const std::string& what) {
    if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        unreadable(what + ": index component type " + std::to_string(type) +
                   " (expected unsigned byte, short or int)");
}

// The accessor's positions, sparse substitution applied.
std::vector<Vec3d> read_positions(const tinygltf::Model& model, int index) {
    const std::string what = "accessor " + std::to_string(index);
    const tinygltf::Accessor& a = accessor_at(model, index, "POSITION");
    if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
        unreadable(what + ": POSITION must be VEC3 of float");
    std::vector<Vec3d> out;
    if (a.bufferView >= 0) {
        const View v = view_of(model, what, a.bufferView, a.byteOffset, a.count, 12, 12);
        out.resize(a.count);
        for (std::size_t i = 0; i < a.count; ++i) {
            float xyz[3];
            std::memcpy(xyz, v.data + i * v.stride, 12);
            out[i] = {double(xyz[0]), double(xyz[1]), double(xyz[2])};
        }
    } else if (!a.sparse.isSparse) {
        unreadable(what + ": no buffer view and not sparse");
    } else {
        // All zeros but the sparse values: bounded by the sparse arrays, not a.count.
        if (a.count > std::size_t(a.sparse.count) * 1024 + 1024)
            unreadable(what + ": " + std::to_string(a.count) + " zero positions for " +
                       std::to_string(a.sparse.count) + " sparse values");
        out.assign(a.count, Vec3d{0, 0, 0});
    }
    if (a.sparse.isSparse) {
        if (a.sparse.count < 0 || static_cast<std::size_t>(a.sparse.count) > a.count)
            unreadable(what + ": sparse count " + std::to_string(a.sparse.count) + " of " + std::to_string(a.count));
        const std::size_t n = static_cast<std::size_t>(a.sparse.count);
        check_index_type(a.sparse.indices.componentType, what + " sparse");
        const std::size_t ib = component_bytes(a.sparse.indices.componentType);
        const View iv = view_of(model, what + " sparse indices", a.sparse.indices.bufferView,
                                static_cast<std::size_t>(std::max(0, a.sparse.indices.byteOffset)), n, ib, ib);
        const View vv = view_of(model, what + " sparse values", a.sparse.values.bufferView,
                                static_cast<std::size_t>(std::max(0, a.sparse.values.byteOffset)), n, 12, 12);
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint32_t at = read_index(iv.data + k * ib, a.sparse.indices.componentType);
            if (at >= out.size())
                unreadable(what + ": sparse index " + std::to_string(at) + " out of range (" +
                           std::to_string(out.size()) + ")");
            float xyz[3];
            std::memcpy(xyz, vv.data + k * 12, 12);
            out[at] = {double(xyz[0]), double(xyz[1]), double(xyz[2])};
        }
    }
    return out;
}

// The primitive's vertex order: its index accessor, or 0, 1, 2, ... without one.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                        std::size_t vertex_count) {
    std::vector<std::uint32_t> out;
    if (prim.indices < 0) {
        out.resize(vertex_count);
        for (std::size_t i = 0; i < vertex_count; ++i) out[i] = static_cast<std::uint32_t>(i);
        return out;
    }
    const std::string what = "accessor " + std::to_string(prim.indices);
    const tinygltf::Accessor& a = accessor_at(model, prim.indices, "indices");
    if (a.type != TINYGLTF_TYPE_SCALAR) unreadable(what + ": indices must be SCALAR");
    check_index_type(a.componentType, what);
    if (a.sparse.isSparse) unreadable(what + ": sparse indices are not supported");
    const std::size_t ib = component_bytes(a.componentType);
    const View v = view_of(model, what, a.bufferView, a.byteOffset, a.count, ib, ib);
    out.resize(a.count);
    for (std::size_t i = 0; i < a.count; ++i) out[i] = read_index(v.data + i * v.stride, a.componentType);
    return out;
}

// Triangles from the primitive's vertex order by its mode; every index checked.
void triangulate(const std::vector<std::uint32_t>& order, int mode, RawMesh& mesh, const std::string& what) {
    const std::size_t n = order.size();
    for (const std::uint32_t i : order)
        if (i >= mesh.positions.size())
            throw ModelError(what + ": index " + std::to_string(i) + " out of range (" +
                             std::to_string(mesh.positions.size()) + " vertices)");
    auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (mesh.triangles.size() / 3 >= kMaxModelTriangles)
            throw ModelError("too many triangles: more than " + std::to_string(kMaxModelTriangles) + " (the limit)");
        mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        mesh.triangles.reserve(n - n % 3);
        for (std::size_t i = 0; i + 2 < n; i += 3) add(order[i], order[i + 1], order[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 0; i + 2 < n; ++i)
            if (i % 2 == 0) add(order[i], order[i + 1], order[i + 2]);
            else add(order[i + 1], order[i], order[i + 2]);  // keeps the strip's winding
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (std::size_t i = 1; i + 1 < n; ++i) add(order[0], order[i], order[i + 1]);
    }
}

bool has_triangles(int mode) {
    return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           mode == TINYGLTF_MODE_TRIANGLE_FAN;
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
