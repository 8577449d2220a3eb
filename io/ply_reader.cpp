// io/ply_reader.cpp — read_ply (model_formats.hpp): octray's own PLY reader.
//
// The format is Greg Turk's, "The PLY Polygon File Format" (1994): a text header of
// elements and their properties (parsed by io/ply_header.cpp), then the data in one of
// three encodings, all read here: `ascii 1.0`, `binary_little_endian 1.0`,
// `binary_big_endian 1.0`.
//
// What is read: element `vertex`'s scalar properties x, y, z (all three required, any
// type) and element `face`'s list `vertex_indices` (or `vertex_index`), integral count
// and index types. Polygons are fanned (v0, vi, vi+1); faces of fewer than three indices
// are left out. Every other element and property is skipped, in all three encodings.
// Elements may come in any order: the vertex count is known from the header, so indices
// are checked as they are read.
//
// Limits, checked before anything is allocated (model_formats.hpp's contract):
// - each element's count against the bytes after the header: a binary element needs at
//   least count * (its smallest row) bytes, lists counted empty; an ASCII value at least
//   two bytes (a character and a separator, bar the file's last), so
//   2 * count * values <= bytes + 1; then all elements together the same way. Counts are
//   uint64 with saturating products, so no count overflows.
// - each list's length against the bytes left, before its items are read;
// - the triangle total against kMaxModelTriangles before a polygon's triangles (n - 2 of
//   n indices) are added;
// - each index against the vertex count: negative or too large is an error.
// Data past the last element is ignored.
#include "ply_header.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace octray::model_formats {

namespace {

using namespace ply;

// ---- binary values -----------------------------------------------------------------

constexpr bool kHostBig = __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__;

template <typename U>
U byteswap(U u) {
    U r = 0;
    for (std::size_t i = 0; i < sizeof(U); ++i) r = static_cast<U>((r << 8) | ((u >> (8 * i)) & 0xFF));
    return r;
}

// One value of type T at p (any alignment), its bytes reversed when `swap`.
template <typename T>
T load(const char* p, bool swap) {
    if constexpr (sizeof(T) == 1) {
        T v;
        std::memcpy(&v, p, 1);
        return v;
    } else {
        using U = std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                     std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>;
        U u;
        std::memcpy(&u, p, sizeof u);
        if (swap) u = byteswap(u);
        T v;
        std::memcpy(&v, &u, sizeof v);
        return v;
    }
}

// A value of type t as R: double for coordinates; std::int64_t for counts and indices,
// whose types the header made integral (a float is never converted to an integer: that
// would be undefined for a large one).
template <typename R>
R load_as(const char* p, Type t, bool swap) {
    constexpr bool floats = std::is_floating_point_v<R>;
    switch (t) {
        case Type::i8: return load<std::int8_t>(p, swap);
        case Type::u8: return load<std::uint8_t>(p, swap);
        case Type::i16: return load<std::int16_t>(p, swap);
        case Type::u16: return load<std::uint16_t>(p, swap);
        case Type::i32: return load<std::int32_t>(p, swap);
        case Type::u32: return load<std::uint32_t>(p, swap);
        case Type::f32: if constexpr (floats) return load<float>(p, swap); else break;
        case Type::f64: if constexpr (floats) return load<double>(p, swap); else break;
    }
    return 0;
}
double load_double(const char* p, Type t, bool swap) { return load_as<double>(p, t, swap); }
std::int64_t load_int(const char* p, Type t, bool swap) { return load_as<std::int64_t>(p, t, swap); }

// ---- the reader --------------------------------------------------------------------

struct Reader {
    std::string_view data;  // the bytes after the header
    std::size_t pos = 0;
    Encoding encoding;
    bool swap;
    std::uint64_t vertex_count = 0;
    RawMesh mesh;

    Reader(std::string_view d, Encoding e)
        : data(d), encoding(e), swap(e != Encoding::ascii && (e == Encoding::big) != kHostBig) {}

    std::size_t left() const { return data.size() - pos; }

    [[noreturn]] static void end_of_file(const Element& e, std::uint64_t row) {
        throw ModelError("unexpected end of file in element '" + e.name + "' (row " + std::to_string(row) + ")");
    }
    static std::string at(const Element& e, std::uint64_t row) { return e.name + " " + std::to_string(row) + ": "; }

    // ASCII: the next whitespace-separated token, or "" at the end of the data.
    std::string_view token() {
        while (pos < data.size() && is_space(data[pos])) ++pos;
        const std::size_t start = pos;
        while (pos < data.size() && !is_space(data[pos])) ++pos;
        return data.substr(start, pos - start);
    }
    std::string_view need_token(const Element& e, std::uint64_t row) {
        const std::string_view t = token();
        if (t.empty()) end_of_file(e, row);
        return t;
    }
    std::int64_t ascii_int(const Element& e, std::uint64_t row) {
        const std::string_view t = need_token(e, row);
        std::int64_t v;
        if (!parse_i64(t, v)) throw ModelError(at(e, row) + "bad integer " + quote(t));
        return v;
    }
    double ascii_double(const Element& e, std::uint64_t row) {
        const std::string_view t = need_token(e, row);
        double v;
        if (!parse_double(t, v)) throw ModelError(at(e, row) + "bad number " + quote(t));
        return v;
    }

    // A list's length: read, not negative, and its items within the bytes left.
    std::uint64_t list_length(const Element& e, std::uint64_t row, const Property& p) {
        std::int64_t n;
        if (encoding == Encoding::ascii) {
            n = ascii_int(e, row);
        } else {
            if (left() < size_of(p.count_type)) end_of_file(e, row);
            n = load_int(data.data() + pos, p.count_type, swap);
            pos += size_of(p.count_type);
        }
        if (n < 0) throw ModelError(at(e, row) + "negative list length " + std::to_string(n));
        const std::uint64_t bytes = encoding == Encoding::ascii ? mul_sat(std::uint64_t(n), 2)
                                                                : mul_sat(std::uint64_t(n), size_of(p.type));
        if (bytes > left() + (encoding == Encoding::ascii ? 1 : 0)) end_of_file(e, row);
        return std::uint64_t(n);
    }

    void skip_value(const Element& e, std::uint64_t row, const Property& p) {
        if (encoding == Encoding::ascii) {
            need_token(e, row);
            return;
        }
        if (left() < size_of(p.type)) end_of_file(e, row);
        pos += size_of(p.type);
    }

    void skip_list(const Element& e, std::uint64_t row, const Property& p) {
        const std::uint64_t n = list_length(e, row, p);
        if (encoding == Encoding::ascii)
            for (std::uint64_t i = 0; i < n; ++i) need_token(e, row);
        else
            pos += static_cast<std::size_t>(n * size_of(p.type));  // checked by list_length
    }

    // Binary rows of scalars only: all `e.count` of them in the bytes left, else the row
    // that is cut off is the one the message names.
    std::size_t fixed_rows_bytes(const Element& e) const {
        if (mul_sat(e.count, e.min_row_bytes) > left()) end_of_file(e, left() / e.min_row_bytes);
        return static_cast<std::size_t>(e.count * e.min_row_bytes);
    }

    void skip_element(const Element& e) {
        if (e.props.empty()) return;
        if (encoding != Encoding::ascii && !e.has_list) {
            pos += fixed_rows_bytes(e);
            return;
        }
        for (std::uint64_t row = 0; row < e.count; ++row)
            for (const Property& p : e.props) p.list ? skip_list(e, row, p) : skip_value(e, row, p);
    }

    // which: the properties x, y and z (see vertex_layout).
    void read_vertices(const Element& e, const int which[3]) {
        mesh.positions.resize(static_cast<std::size_t>(e.count));  // count checked against the bytes
        if (encoding != Encoding::ascii && !e.has_list) return read_fixed_vertices(e, which);
        for (std::uint64_t row = 0; row < e.count; ++row) {
            double xyz[3] = {0, 0, 0};
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Property& p = e.props[i];
                const int k = int(i) == which[0] ? 0 : int(i) == which[1] ? 1 : int(i) == which[2] ? 2 : -1;
                if (p.list) {
                    skip_list(e, row, p);
                } else if (k < 0) {
                    skip_value(e, row, p);
                } else if (encoding == Encoding::ascii) {
                    xyz[k] = ascii_double(e, row);
                } else {
                    if (left() < size_of(p.type)) end_of_file(e, row);
                    xyz[k] = load_double(data.data() + pos, p.type, swap);
                    pos += size_of(p.type);
                }
            }
            mesh.positions[static_cast<std::size_t>(row)] = {xyz[0], xyz[1], xyz[2]};
        }
    }

    // Binary rows of scalars only: one stride, x y z at fixed offsets. The common case
    // (three floats in the host's byte order) gets a loop of its own.
    void read_fixed_vertices(const Element& e, const int which[3]) {
        std::size_t offset[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < which[k]; ++i) offset[k] += size_of(e.props[std::size_t(i)].type);
        const Type tx = e.props[std::size_t(which[0])].type, ty = e.props[std::size_t(which[1])].type,
                   tz = e.props[std::size_t(which[2])].type;
        const std::size_t stride = e.min_row_bytes, n = static_cast<std::size_t>(e.count);
        const std::size_t bytes = fixed_rows_bytes(e);
        const char* p = data.data() + pos;
        Vec3d* out = mesh.positions.data();
        if (!swap && tx == Type::f32 && ty == Type::f32 && tz == Type::f32) {
            for (std::size_t v = 0; v < n; ++v, p += stride) {
                float x, y, z;
                std::memcpy(&x, p + offset[0], 4);
                std::memcpy(&y, p + offset[1], 4);
                std::memcpy(&z, p + offset[2], 4);
                out[v] = {x, y, z};
            }
        } else {
            for (std::size_t v = 0; v < n; ++v, p += stride)
                out[v] = {load_double(p + offset[0], tx, swap), load_double(p + offset[1], ty, swap),
                          load_double(p + offset[2], tz, swap)};
        }
        pos += bytes;
    }

    // The throws are out of line, so that the checks of every index inline small.
    [[noreturn]] void bad_index(const Element& e, std::uint64_t row, std::int64_t i) const {
        throw ModelError(at(e, row) + "index " + std::to_string(i) + " out of range (" + std::to_string(vertex_count) +
                         " vertices)");
    }
    [[noreturn]] static void too_many_triangles() {
        throw ModelError("too many triangles: more than " + std::to_string(kMaxModelTriangles) + " (the limit)");
    }

    std::uint32_t index(const Element& e, std::uint64_t row, std::int64_t i) const {
        if (i < 0 || std::uint64_t(i) >= vertex_count) bad_index(e, row, i);
        return static_cast<std::uint32_t>(i);  // read from at most 32 bits: fits
    }

    // A polygon's indices become triangles (first, prev, v) as they are read.
    struct Fan {
        std::uint32_t first = 0, prev = 0;
        std::uint64_t triangles = 0;
    };
    // A polygon of n indices adds n - 2 triangles: counted before any is added.
    static void count_polygon(Fan& f, std::uint64_t n) {
        if (n < 3) return;
        if (n - 2 > kMaxModelTriangles - f.triangles) too_many_triangles();
        f.triangles += n - 2;
    }
    void fan(Fan& f, std::uint64_t k, std::uint32_t v) {
        if (k == 0) f.first = v;
        if (k >= 2) {
            mesh.triangles.push_back(f.first);
            mesh.triangles.push_back(f.prev);
            mesh.triangles.push_back(v);
        }
        f.prev = v;
    }

    void read_faces(const Element& e, std::size_t list_prop) {
        const Property& lp = e.props[list_prop];
        // Room for as many triangles as the data could hold, within the limit.
        std::uint64_t room = e.count;
        if (encoding == Encoding::ascii)
            room = std::min<std::uint64_t>(room, (left() + 1) / (2 * (e.props.size() + 3)));
        else
            room = std::min<std::uint64_t>(room, left() / (e.min_row_bytes + 3 * size_of(lp.type)));
        room = std::min<std::uint64_t>(room, kMaxModelTriangles);
        mesh.triangles.reserve(static_cast<std::size_t>(room) * 3);
        Fan f;
        if (encoding != Encoding::ascii && e.props.size() == 1 && lp.count_type == Type::u8) {
            if (lp.type == Type::i32) return read_plain_faces<std::int32_t>(e, f);
            if (lp.type == Type::u32) return read_plain_faces<std::uint32_t>(e, f);
        }
        for (std::uint64_t row = 0; row < e.count; ++row)
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Property& p = e.props[i];
                if (i != list_prop) {
                    p.list ? skip_list(e, row, p) : skip_value(e, row, p);
                    continue;
                }
                const std::uint64_t n = list_length(e, row, p);
                count_polygon(f, n);
                for (std::uint64_t k = 0; k < n; ++k) {
                    std::int64_t raw;
                    if (encoding == Encoding::ascii) {
                        raw = ascii_int(e, row);
                    } else {
                        raw = load_int(data.data() + pos, p.type, swap);  // in the bytes: list_length
                        pos += size_of(p.type);
                    }
                    fan(f, k, index(e, row, raw));
                }
            }
    }

    // Binary faces of the index list alone, uchar counts and 32-bit indices (what most
    // writers write, save_ply too): a loop of their own.
    template <typename I>
    void read_plain_faces(const Element& e, Fan& f) {
        const char* d = data.data();
        for (std::uint64_t row = 0; row < e.count; ++row) {
            if (pos >= data.size()) end_of_file(e, row);
            const std::size_t n = static_cast<unsigned char>(d[pos++]);
            if (n * sizeof(I) > left()) end_of_file(e, row);
            count_polygon(f, n);
            for (std::size_t k = 0; k < n; ++k, pos += sizeof(I)) fan(f, k, index(e, row, load<I>(d + pos, swap)));
        }
    }
};

// The indices of the vertex element's scalar properties x, y and z.
void vertex_layout(const Element& e, int which[3]) {
    static constexpr const char* kAxis[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k) which[k] = -1;
    for (std::size_t i = 0; i < e.props.size(); ++i)
        for (int k = 0; k < 3; ++k)
            if (which[k] < 0 && e.props[i].name == kAxis[k]) which[k] = int(i);
    for (int k = 0; k < 3; ++k) {
        if (which[k] < 0) throw ModelError(std::string("element 'vertex' has no property '") + kAxis[k] + "'");
        if (e.props[std::size_t(which[k])].list)
            throw ModelError(std::string("vertex property '") + kAxis[k] + "' is a list");
    }
}

RawModel read(std::string_view bytes) {
    const Header h = parse_header(bytes);
    const std::string_view data = bytes.substr(h.data_offset);

    const Element* vertex = nullptr;
    std::size_t list_prop = 0;
    for (const Element& e : h.elements) {
        if (e.name == "vertex") vertex = &e;
        if (e.name != "face") continue;
        bool found = false;
        for (std::size_t i = 0; i < e.props.size() && !found; ++i) {
            const Property& p = e.props[i];
            if (p.name != "vertex_indices" && p.name != "vertex_index") continue;
            if (!p.list) throw ModelError("face property '" + p.name + "' is not a list");
            if (!integral(p.type)) throw ModelError("face property '" + p.name + "' has a non-integer index type");
            list_prop = i;
            found = true;
        }
        if (!found) throw ModelError("element 'face' has no list 'vertex_indices'");
    }
    if (!vertex) throw ModelError("no element 'vertex'");
    int which[3];
    vertex_layout(*vertex, which);
    check_counts(h, data.size());

    Reader r(data, h.encoding);
    r.vertex_count = vertex->count;  // known before any face is read, whatever the order
    for (const Element& e : h.elements) {
        if (&e == vertex) r.read_vertices(e, which);
        else if (e.name == "face") r.read_faces(e, list_prop);
        else r.skip_element(e);
    }
    RawModel model;
    model.meshes.push_back(std::move(r.mesh));
    model.instance_each_mesh();
    return model;
}

}  // namespace

RawModel read_ply(std::string_view bytes) {
    try {
        return read(bytes);
    } catch (const std::bad_alloc&) {
        throw ModelError("out of memory reading the model");
    } catch (const std::length_error&) {
        throw ModelError("out of memory reading the model");
    }
}

}  // namespace octray::model_formats
