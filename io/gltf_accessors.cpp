// io/gltf_accessors.cpp — read_positions, read_indices, triangulate (gltf_accessors.hpp):
// a glTF accessor's elements, `stride` apart in a buffer view, the view a range of its
// buffer (Khronos, "glTF 2.0 Specification" §3.6). count·stride is checked against the
// view and the view against its buffer before anything is copied:
// "accessor 3: 2000000000 elements of 12 bytes run past buffer view 0 (12 bytes)".
#include "gltf_accessors.hpp"

#include <algorithm>
#include <cstring>

namespace octray::model_formats::gltf {

namespace {

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

}  // namespace

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

}  // namespace octray::model_formats::gltf
