// io/model_loader.cpp — see model_loader.hpp.
//
// How a file is read:
// 1. The extension picks the format; the file must exist, be a regular file and be at
//    most kMaxModelFileBytes. It is read into memory whole (its size known first).
// 2. The format's reader (model_formats.hpp) turns the bytes into a RawModel: meshes of
//    positions and triangles, every index checked, every count checked against the bytes
//    that could hold it before anything of that size is allocated.
// 3. collect_model applies instance and user transforms in double, checks finiteness,
//    shares vertices by exact position and drops zero-area triangles.
// Every reader is compiled into octray's own units (no prebuilt parser runs), so the
// sanitizer builds and the fuzz targets (fuzz/) see all of it: docs/reliability.md.
#include "model_loader.hpp"

#include "model_formats.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

namespace octray {

namespace {

struct Format {
    const char* extension;
    const char* name;  // MeshData::format
};
constexpr Format kFormats[] = {
    {".gltf", "glTF 2.0"},
    {".glb", "glTF 2.0"},
    {".obj", "Wavefront OBJ"},
    {".ply", "PLY"},
};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

// The whole file, after checking that it is a regular file within the size limit.
std::string read_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw ModelError(std::string("cannot open: ") + std::strerror(EISDIR));
    std::ifstream in(path, std::ios::binary);
    if (!in) throw ModelError(std::string("cannot open: ") + std::strerror(errno));
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) throw ModelError("cannot open: " + ec.message());
    if (size > kMaxModelFileBytes)
        throw ModelError("file too large: " + std::to_string(size) + " bytes (limit " +
                         std::to_string(kMaxModelFileBytes) + ")");
    std::string bytes(static_cast<std::size_t>(size), '\0');
    if (size > 0) in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) throw ModelError("cannot read the whole file");
    return bytes;
}

}  // namespace

MeshData load_model(const std::string& path, const MeshTransform& transform) {
    if (const std::string p = transform.problem(); !p.empty()) throw ModelError("transform: " + p);
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    const Format* format = nullptr;
    for (const Format& f : kFormats)
        if (ext == f.extension) format = &f;
    if (!format) throw ModelError("unknown model format '" + ext + "' (expected .gltf, .glb, .obj or .ply)");
    try {
        const std::string bytes = read_file(path);
        model_formats::RawModel raw;
        if (ext == ".ply") raw = model_formats::read_ply(bytes);
        else if (ext == ".obj") raw = model_formats::read_obj(bytes);
        else raw = model_formats::read_gltf(bytes, ext == ".glb", std::filesystem::path(path).parent_path());
        return model_formats::collect_model(raw, transform.to_matrix(), format->name);
    } catch (const std::bad_alloc&) {
        throw ModelError("out of memory reading the model");
    }
}

}  // namespace octray
