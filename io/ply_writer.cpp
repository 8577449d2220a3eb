// io/ply_writer.cpp — save_ply (model_loader.hpp): a mesh as a binary little-endian PLY
// file (Greg Turk, "The PLY Polygon File Format", 1994), written directly: float x y z
// per vertex, and per face a uchar count 3 and three int indices. Everything is checked
// before the file is opened, so a refused mesh leaves no file behind.
#include "model_loader.hpp"

#include "model_math.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>

namespace octray {

using namespace model_math;

namespace {

// Appends v's bytes, least significant first, whatever the host's byte order.
template <typename T>
void put_le(std::string& out, T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    if constexpr (__BYTE_ORDER__ == __ORDER_BIG_ENDIAN__)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    out.append(reinterpret_cast<const char*>(b), sizeof b);
}

}  // namespace

void save_ply(const MeshData& mesh, const std::string& path) {
    auto fail = [&](const std::string& what) { return ModelError("cannot write " + path + ": " + what); };
    if (mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        throw fail("no triangles, or an index count that is not a multiple of 3");
    if (mesh.vertices.size() > 0x7FFFFFFFu) throw fail("too many vertices");  // indices are int
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
        const Vec3d& p = mesh.vertices[v];
        // The floats themselves are checked: no double made of them to be optimized away.
        if (!std::isfinite(static_cast<float>(p.x)) || !std::isfinite(static_cast<float>(p.y)) ||
            !std::isfinite(static_cast<float>(p.z)))
            throw fail("vertex " + std::to_string(v) + " " + vec_str(p) + " does not fit in float");
    }
    for (const std::uint32_t i : mesh.indices)
        if (i >= mesh.vertices.size())
            throw fail("index " + std::to_string(i) + " out of range (" + std::to_string(mesh.vertices.size()) +
                       " vertices)");

    errno = 0;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw fail(errno != 0 ? std::strerror(errno) : "cannot open");
    out << "ply\nformat binary_little_endian 1.0\ncomment written by octray\n"
        << "element vertex " << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << mesh.indices.size() / 3 << "\nproperty list uchar int vertex_indices\nend_header\n";
    // The data goes out a block at a time: memory stays small whatever the mesh's size.
    constexpr std::size_t kBlock = 1 << 20;
    std::string block;
    block.reserve(kBlock + 16);
    auto flush = [&](bool last) {
        if (block.size() >= kBlock || (last && !block.empty())) {
            out.write(block.data(), static_cast<std::streamsize>(block.size()));
            block.clear();
        }
    };
    for (const Vec3d& p : mesh.vertices) {
        put_le(block, float(p.x));
        put_le(block, float(p.y));
        put_le(block, float(p.z));
        flush(false);
    }
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        block.push_back(3);
        for (std::size_t k = 0; k < 3; ++k) put_le(block, static_cast<std::int32_t>(mesh.indices[t + k]));
        flush(false);
    }
    flush(true);
    out.close();
    if (!out) throw fail("write failed");
}

}  // namespace octray
