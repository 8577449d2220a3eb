// tests/test_model_ply.cpp — read_ply (io/ply_reader.cpp) and save_ply (io/ply_writer.cpp).
//
// The files are made here by a small writer of the tests' own (make_ply), which lays out
// every binary value byte by byte with shifts in the named byte order, so the reader's
// loads are checked against an encoding they do not share. Expected meshes are written
// out by hand from the faces, fanned (v0, vi, vi+1).
#include "model_fixtures.hpp"
#include "model_formats.hpp"
#include "model_loader.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace octray;
using namespace octray::model_formats;
using namespace model_fixtures;

namespace {

enum class Enc { ascii, le, be };

struct Prop {
    std::string type, name;
    std::string count_type;  // non-empty: a list of `type` with this count type
};
using Row = std::vector<std::vector<double>>;  // one value per scalar, the items per list
struct Elem {
    std::string name;
    std::vector<Prop> props;
    std::vector<Row> rows;
};

std::size_t type_bytes(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "double" || t == "float64") return 8;
    return 4;
}

void put(std::string& out, const std::string& type, double v, Enc enc) {
    const bool is_float = type == "float" || type == "float32";
    const bool is_double = type == "double" || type == "float64";
    if (enc == Enc::ascii) {
        std::ostringstream o;
        o.precision(17);
        if (is_float || is_double) o << v;
        else o << static_cast<std::int64_t>(v);
        out += o.str() + " ";
        return;
    }
    std::uint64_t bits;
    if (is_float) {
        const float f = static_cast<float>(v);
        std::uint32_t u;
        std::memcpy(&u, &f, 4);
        bits = u;
    } else if (is_double) {
        std::memcpy(&bits, &v, 8);
    } else {
        bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(v));  // two's complement, cut below
    }
    const std::size_t n = type_bytes(type);
    for (std::size_t i = 0; i < n; ++i)
        out.push_back(static_cast<char>((bits >> (8 * (enc == Enc::le ? i : n - 1 - i))) & 0xFF));
}

std::string header(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
    const char* format = enc == Enc::ascii ? "ascii" : enc == Enc::le ? "binary_little_endian" : "binary_big_endian";
    std::string h = "ply" + eol + "format " + format + " 1.0" + eol + "comment made by test_model_ply" + eol;
    for (const Elem& e : elems) {
        h += "element " + e.name + " " + std::to_string(e.rows.size()) + eol;
        for (const Prop& p : e.props)
            h += p.count_type.empty() ? "property " + p.type + " " + p.name + eol
                                      : "property list " + p.count_type + " " + p.type + " " + p.name + eol;
    }
    return h + "end_header" + eol;
}

std::string body(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
    std::string b;
    for (const Elem& e : elems)
        for (const Row& r : e.rows) {
            for (std::size_t i = 0; i < e.props.size(); ++i) {
                const Prop& p = e.props[i];
                if (!p.count_type.empty()) put(b, p.count_type, double(r[i].size()), enc);
                for (const double v : r[i]) put(b, p.type, v, enc);
            }
            if (enc == Enc::ascii) b += eol;
        }
    return b;
}

std::string make_ply(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
    return header(elems, enc, eol) + body(elems, enc, eol);
}

// The small mesh every encoding writes: positions exact in float; a quad, a triangle, a
// two-index face and an empty one (both left out), a pentagon.
const std::vector<Vec3d> kPositions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 2.25, -1.5}};
const std::vector<std::vector<double>> kFaces = {{0, 1, 2, 3}, {1, 4, 2}, {3, 0}, {}, {0, 1, 4, 2, 3}};
const std::vector<std::uint32_t> kTriangles = {0, 1, 2, 0, 2, 3,  // quad
                                               1, 4, 2,           // triangle
                                               0, 1, 4, 0, 4, 2, 0, 2, 3};  // pentagon

Elem vertices(const std::string& type = "float") {
    Elem e{"vertex", {{type, "x", ""}, {type, "y", ""}, {type, "z", ""}}, {}};
    for (const Vec3d& p : kPositions) e.rows.push_back({{p.x}, {p.y}, {p.z}});
    return e;
}

Elem faces(const std::string& count_type = "uchar", const std::string& index_type = "int",
           const std::string& name = "vertex_indices") {
    Elem e{"face", {{index_type, name, count_type}}, {}};
    for (const auto& f : kFaces) e.rows.push_back({f});
    return e;
}

// One mesh, one identity instance, these positions exactly and these triangles.
void check_mesh(const RawModel& m, const std::vector<Vec3d>& positions, const std::vector<std::uint32_t>& triangles) {
    REQUIRE(m.meshes.size() == 1);
    REQUIRE(m.instances.size() == 1);
    CHECK(m.instances[0].mesh == 0);
    CHECK(m.meshes[0].name.empty());
    const RawMesh& mesh = m.meshes[0];
    REQUIRE(mesh.positions.size() == positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        CAPTURE(v);
        CHECK(mesh.positions[v].x == positions[v].x);
        CHECK(mesh.positions[v].y == positions[v].y);
        CHECK(mesh.positions[v].z == positions[v].z);
    }
    CHECK(mesh.triangles == triangles);
}

void check_small_mesh(const RawModel& m) { check_mesh(m, kPositions, kTriangles); }

// read_ply's ModelError message; any other exception fails the test where it is thrown.
std::string ply_error(const std::string& bytes) {
    try {
        read_ply(bytes);
    } catch (const ModelError& e) {
        return e.what();
    }
    return "(read without error)";
}

const Enc kEncodings[] = {Enc::ascii, Enc::le, Enc::be};
const char* enc_name(Enc e) { return e == Enc::ascii ? "ascii" : e == Enc::le ? "little-endian" : "big-endian"; }

}  // namespace

TEST_CASE("read_ply: the three encodings of one mesh read the same, polygons fanned") {
    // The binary layout spelled out once, so the writer above is checked too: vertex 4
    // (0.5, 2.25, -1.5) as little-endian floats, then the quad as uchar 4 and ints.
    const std::string le = make_ply({vertices(), faces()}, Enc::le);
    const std::string data = le.substr(le.find("end_header\n") + 11);
    const std::string v4 = data.substr(4 * 12, 12);
    CHECK(v4 == std::string("\x00\x00\x00\x3f\x00\x00\x10\x40\x00\x00\xc0\xbf", 12));
    CHECK(data.substr(5 * 12, 17) == std::string("\x04\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00\x03\x00\x00\x00", 17));
    const std::string be = make_ply({vertices(), faces()}, Enc::be);
    CHECK(be.substr(be.find("end_header\n") + 11 + 4 * 12, 12) ==
          std::string("\x3f\x00\x00\x00\x40\x10\x00\x00\xbf\xc0\x00\x00", 12));

    for (const Enc enc : kEncodings)
        for (const char* type : {"float", "double", "float32", "float64"}) {
            INFO("encoding: " << std::string(enc_name(enc)));
            INFO("type: " << std::string(type));
            check_small_mesh(read_ply(make_ply({vertices(type), faces()}, enc)));
        }
    // Integer coordinates, and every integral count and index type.
    Elem ints{"vertex", {{"short", "x", ""}, {"int", "y", ""}, {"char", "z", ""}}, {}};
    for (const Vec3d& p : {Vec3d{0, 0, 0}, Vec3d{-300, 70000, -5}, Vec3d{1, 2, 3}, Vec3d{4, 5, 6}, Vec3d{7, 8, 9}})
        ints.rows.push_back({{p.x}, {p.y}, {p.z}});
    for (const Enc enc : kEncodings)
        for (const char* ct : {"uchar", "char", "ushort", "short", "uint", "int", "uint8", "int32"})
            for (const char* it : {"uchar", "char", "ushort", "short", "uint", "int", "uint32", "int16"}) {
                INFO("encoding: " << std::string(enc_name(enc)));
                INFO("count type: " << std::string(ct) << ", index type: " << std::string(it));
                const RawModel m = read_ply(make_ply({ints, faces(ct, it)}, enc));
                REQUIRE(m.meshes.size() == 1);
                CHECK(m.meshes[0].triangles == kTriangles);
                CHECK(m.meshes[0].positions[1].x == -300);
                CHECK(m.meshes[0].positions[1].y == 70000);
                CHECK(m.meshes[0].positions[1].z == -5);
            }
    // `vertex_index`, the other name.
    check_small_mesh(read_ply(make_ply({vertices(), faces("uchar", "int", "vertex_index")}, Enc::ascii)));
}

TEST_CASE("read_ply: \\r\\n line ends, faces before vertices, no face element") {
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        check_small_mesh(read_ply(make_ply({vertices(), faces()}, enc, "\r\n")));
        check_small_mesh(read_ply(make_ply({faces(), vertices()}, enc)));
        // No faces: the positions, no triangles; collect_model says so.
        const RawModel m = read_ply(make_ply({vertices()}, enc));
        REQUIRE(m.meshes.size() == 1);
        CHECK(m.meshes[0].positions.size() == kPositions.size());
        CHECK(m.meshes[0].triangles.empty());
        CHECK_THROWS_WITH_AS(collect_model(m, MeshTransform{}.to_matrix(), "PLY"), "no triangles", ModelError);
    }
    // Header words apart by tabs and runs of spaces, trailing spaces (assimp's cube.ply),
    // a line of no keyword passed over, obj_info; trailing bytes after the data ignored.
    const std::string h =
        "ply \nformat\tascii  1.0   \nobj_info made by hand\nCreated by Blender3D 247\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    const RawModel m = read_ply(h + "0 0 0\n+1 0 0\n0 1.0e0 0\n3 0 1 +2\nanything after\n");
    CHECK(m.meshes[0].triangles == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(m.meshes[0].positions[1].x == 1);
    CHECK(m.meshes[0].positions[2].y == 1);
}

TEST_CASE("read_ply: other properties and elements, lists included, are skipped in every encoding") {
    Elem v{"vertex",
           {{"uchar", "red", ""}, {"double", "z", ""}, {"float", "weights", "uchar"}, {"short", "nx", ""},
            {"float", "x", ""}, {"uint", "flags", ""}, {"int", "y", ""}, {"double", "confidence", ""}},
           {}};
    for (std::size_t i = 0; i < kPositions.size(); ++i) {
        const Vec3d& p = kPositions[i];
        Row r = {{200}, {p.z}, {}, {-7}, {p.x}, {4000000000.0}, {0}, {0.25}};
        r[2].assign(i, 1.5);  // lists of 0 to 4 weights
        r[6] = {p.y == 2.25 ? 2.0 : p.y};  // y is an int here
        v.rows.push_back(r);
    }
    Elem f{"face", {{"uchar", "flags", ""}, {"int", "vertex_indices", "uchar"}, {"float", "texcoord", "int"}}, {}};
    for (const auto& face : kFaces) f.rows.push_back({{9}, face, std::vector<double>(2 * face.size(), 0.5)});
    Elem edge{"edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}, {"uint", "path", "ushort"}}, {}};
    for (int i = 0; i < 4; ++i) edge.rows.push_back({{double(i)}, {double(i + 1)}, std::vector<double>(i * 3, 99)});
    Elem material{"material", {{"float", "ambient", ""}, {"uchar", "name", "uint"}}, {{{0.5}, {65, 66}}, {{1}, {}}}};
    Elem empty{"nothing", {}, {{}, {}, {}}};  // properties none, rows three: no bytes

    std::vector<Vec3d> want = kPositions;
    want[4].y = 2;
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        check_mesh(read_ply(make_ply({material, v, edge, f, empty, material}, enc)), want, kTriangles);
    }
}

TEST_CASE("read_ply: counts the bytes cannot hold are refused before anything is allocated") {
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        const char* format = enc == Enc::ascii ? "ascii" : enc == Enc::le ? "binary_little_endian" : "binary_big_endian";
        auto file = [&](const std::string& vcount, const std::string& fcount, std::size_t total) {
            std::string h = std::string("ply\nformat ") + format + " 1.0\nelement vertex " + vcount +
                            "\nproperty float x\nproperty float y\nproperty float z\nelement face " + fcount +
                            "\nproperty list uchar int vertex_indices\nend_header\n";
            const std::size_t after = total > h.size() ? total - h.size() : 0;
            return std::pair<std::string, std::size_t>{h + std::string(after, '1'), after};
        };
        // 2^31 vertices in a 200-byte file.
        auto [bytes, after] = file("2147483648", "0", 200);
        REQUIRE(bytes.size() == 200);
        CHECK(ply_error(bytes) == "vertex count 2147483648 does not fit in the file's " + std::to_string(after) +
                                      " bytes after the header");
        // Faces: huge, at uint64's limit, past it.
        std::tie(bytes, after) = file("3", "1099511627776", 300);
        CHECK(ply_error(bytes) == "face count 1099511627776 does not fit in the file's " + std::to_string(after) +
                                      " bytes after the header");
        std::tie(bytes, after) = file("3", "18446744073709551615", 300);
        CHECK(ply_error(bytes) == "face count 18446744073709551615 does not fit in the file's " +
                                      std::to_string(after) + " bytes after the header");
        std::tie(bytes, after) = file("3", "18446744073709551616", 300);
        CHECK(ply_error(bytes) == "header line 7: bad element count '18446744073709551616'");
        std::tie(bytes, after) = file("-1", "0", 300);
        CHECK(ply_error(bytes) == "header line 3: bad element count '-1'");
        // Each fits alone, not both: binary needs 12 bytes a vertex and 1 a face (181 in
        // 180), ASCII 2 bytes a value, 3 a vertex and 1 a face, less one (162 in 160 + 1).
        const std::uint64_t v = 10, f = enc == Enc::ascii ? 51 : 61;
        std::tie(bytes, after) = file(std::to_string(v), std::to_string(f), 0);
        const std::size_t room = enc == Enc::ascii ? 160 : 180;
        bytes += std::string(room, '1');
        const std::uint64_t need = enc == Enc::ascii ? 2 * (3 * v + f) : 12 * v + f;
        CHECK(ply_error(bytes) == "the element counts need at least " + std::to_string(need) +
                                      " bytes, the file has " + std::to_string(room) + " after the header");
    }
    // Exactly as much as the counts need is not refused by them (binary: 3 vertices of
    // 12 bytes, one empty face).
    const std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\n";
    const RawModel m = read_ply(h + std::string(37, '\0'));
    CHECK(m.meshes[0].positions.size() == 3);
    CHECK(m.meshes[0].triangles.empty());
}

TEST_CASE("read_ply: a polygon past the triangle limit is refused before its triangles are stored") {
    // One face of kMaxModelTriangles + 3 one-byte indices: one triangle too many.
    const std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uint uchar vertex_indices\nend_header\n";
    const std::uint64_t n = kMaxModelTriangles + 3;
    std::string bytes = h + std::string(36, '\0');
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((n >> (8 * i)) & 0xFF));
    bytes += std::string(n, '\0');
    CHECK(ply_error(bytes) == "too many triangles: more than " + std::to_string(kMaxModelTriangles) + " (the limit)");
}

TEST_CASE("read_ply: lists and data cut short are errors naming the element and row") {
    for (const Enc enc : {Enc::le, Enc::be}) {
        INFO("encoding: " << std::string(enc_name(enc)));
        // A face's count says 255 (and 2^32 - 1) where 3 indices follow.
        for (const char* ct : {"uchar", "uint"}) {
            Elem f = faces(ct);
            std::string bytes = make_ply({vertices(), f}, enc);
            const std::size_t first_face = bytes.find("end_header\n") + 11 + 5 * 12;
            const std::size_t n = type_bytes(ct);
            for (std::size_t i = 0; i < n; ++i) bytes[first_face + i] = '\xff';
            CHECK(ply_error(bytes) == "unexpected end of file in element 'face' (row 0)");
        }
    }
    CHECK(ply_error(header({vertices(), faces()}, Enc::ascii) + "0 0 0\n1 0 0\n0 1 0\n1 1 1\n2 2 2\n1000000 0 1 2\n") ==
          "unexpected end of file in element 'face' (row 0)");

    // Every cut of a binary file fails; where the counts still fit, the message names the
    // row cut off, found here from the layout: faces (quads: 1 + 16 bytes, past the
    // 1 byte a face the count check assumes) first, then vertices of 12 bytes.
    Elem quads{"face", {{"int", "vertex_indices", "uchar"}}, {}};
    for (int i = 0; i < 6; ++i) quads.rows.push_back({{0, 1, 2, 3}});
    for (const Enc enc : {Enc::le, Enc::be}) {
        INFO("encoding: " << std::string(enc_name(enc)));
        const std::string whole = make_ply({quads, vertices()}, enc);
        const std::size_t start = whole.find("end_header\n") + 11;
        REQUIRE(whole.size() == start + 6 * 17 + 5 * 12);
        CHECK(read_ply(whole).meshes[0].triangles.size() == 6 * 6);
        for (std::size_t cut = start; cut < whole.size(); ++cut) {
            CAPTURE(cut);
            const std::size_t data = cut - start;
            const std::string d = std::to_string(data);
            std::string want;  // the checks in the reader's order: each count, the sum, the rows
            if (data < 6) want = "face count 6 does not fit in the file's " + d + " bytes after the header";
            else if (data < 60) want = "vertex count 5 does not fit in the file's " + d + " bytes after the header";
            else if (data < 66) want = "the element counts need at least 66 bytes, the file has " + d + " after the header";
            else if (data < 102) want = "unexpected end of file in element 'face' (row " + std::to_string(data / 17) + ")";
            else want = "unexpected end of file in element 'vertex' (row " + std::to_string((data - 102) / 12) + ")";
            CHECK(ply_error(whole.substr(0, cut)) == want);
        }
    }
    // ASCII cut in the middle of the vertices: the first row without its values.
    const std::string ascii = make_ply({faces(), vertices()}, Enc::ascii);
    REQUIRE(ascii.substr(ascii.size() - 6) == "-1.5 \n");
    CHECK(ply_error(ascii.substr(0, ascii.size() - 6)) == "unexpected end of file in element 'vertex' (row 4)");
}

TEST_CASE("read_ply: indices out of range and negative list lengths are errors") {
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        Elem f = faces();
        f.rows[1][0] = {1, 5, 2};
        CHECK(ply_error(make_ply({vertices(), f}, enc)) == "face 1: index 5 out of range (5 vertices)");
        f.rows[1][0] = {1, 4, -1};
        CHECK(ply_error(make_ply({vertices(), f}, enc)) == "face 1: index -1 out of range (5 vertices)");
        // Faces first: the vertex count comes from the header.
        f.rows[1][0] = {99, 4, 1};
        CHECK(ply_error(make_ply({f, vertices()}, enc)) == "face 1: index 99 out of range (5 vertices)");
        // A point's index is checked too, though the point is left out.
        f = faces();
        f.rows[2][0] = {7};
        CHECK(ply_error(make_ply({vertices(), f}, enc)) == "face 2: index 7 out of range (5 vertices)");
        f = faces("uchar", "uint");
        f.rows[4][0][3] = 4294967295.0;
        CHECK(ply_error(make_ply({vertices(), f}, enc)) == "face 4: index 4294967295 out of range (5 vertices)");
        f = faces("char", "int");
        f.rows[3][0] = {0, 1, 2};
        std::string bytes = make_ply({vertices(), f}, enc);
        if (enc == Enc::ascii) {
            const std::size_t at = bytes.rfind("3 0 1 2");
            bytes.replace(at, 7, "-3 0 1 2");
        } else {
            const std::size_t at = bytes.find("end_header\n") + 11 + 5 * 12 + 17 + 13 + 9;  // face 3's count
            REQUIRE(bytes[at] == 3);
            bytes[at] = '\xfd';
        }
        CHECK(ply_error(bytes) == "face 3: negative list length -3");
    }
}

TEST_CASE("read_ply: broken headers and ASCII numbers are errors with the line") {
    const std::string h3 = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string ok = "ply\nformat ascii 1.0\n" + h3 + "end_header\n0 0 0\n1 0 0\n0 1 0\n";
    REQUIRE(read_ply(ok).meshes[0].positions.size() == 3);
    CHECK(ply_error("") == "not a ply file: no 'ply' line at the start");
    CHECK(ply_error("solid cube\n") == "not a ply file: no 'ply' line at the start");
    CHECK(ply_error("plyformat ascii 1.0\n") == "not a ply file: no 'ply' line at the start");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "0 0 0\n1 0 0\n0 1 0\n") == "missing end_header");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "end_headers\n0 0 0\n") == "missing end_header");
    CHECK(ply_error("ply\n" + h3 + "end_header\n") == "missing format line");
    CHECK(ply_error("ply\nformat binary_middle_endian 1.0\n" + h3 + "end_header\n") ==
          "header line 2: unknown format 'binary_middle_endian'");
    CHECK(ply_error("ply\nformat ascii 2.0\n" + h3 + "end_header\n") == "header line 2: unknown format version '2.0'");
    CHECK(ply_error("ply\nformat ascii\n" + h3 + "end_header\n") == "bad header line 2: 'format ascii'");
    CHECK(ply_error("ply\nformat ascii 1.0\nformat ascii 1.0\n" + h3 + "end_header\n") ==
          "bad header line 3: 'format ascii 1.0'");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement vertex\n") == "bad header line 3: 'element vertex'");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float33 x\n") ==
          "header line 4: unknown type 'float33'");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty int64 x\n") ==
          "header line 4: unknown type 'int64'");
    CHECK(ply_error("ply\nformat ascii 1.0\nproperty float x\n") == "header line 3: property before any element");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "property list float int vertex_indices\nend_header\n") ==
          "header line 7: list count type 'float' is not an integer type");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "property list uchar\nend_header\n") ==
          "bad header line 7: 'property list uchar'");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + h3 + "end_header\n") == "header line 7: a second element 'vertex'");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float z\nend_header\n") ==
          "element 'vertex' has no property 'y'");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property list uchar float z\nend_header\n") == "vertex property 'z' is a list");
    CHECK(ply_error("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n") ==
          "no element 'vertex'");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "element face 0\nproperty list uchar float vertex_indices\nend_header\n") ==
          "face property 'vertex_indices' has a non-integer index type");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "element face 0\nproperty int vertex_indices\nend_header\n") ==
          "face property 'vertex_indices' is not a list");
    CHECK(ply_error("ply\nformat ascii 1.0\n" + h3 + "element face 0\nproperty list uchar int corners\nend_header\n") ==
          "element 'face' has no list 'vertex_indices'");
    // Messages stay one line, and short, whatever the header holds.
    const std::string msg = ply_error("ply\r\nformat ascii 1.0\r\nelement vertex 3 \x01\x02" + std::string(200, 'x') + "\r\n");
    CHECK(msg.rfind("bad header line 3: 'element vertex 3 ??xxx", 0) == 0);
    CHECK(msg.size() < 80);

    const std::string head = "ply\nformat ascii 1.0\n" + h3 + "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    CHECK(ply_error(head + "0 0 0\n1 0.5abc 0\n0 1 0\n3 0 1 2\n") == "vertex 1: bad number '0.5abc'");
    CHECK(ply_error(head + "0 0 0\n1 , 0\n0 1 0\n3 0 1 2\n") == "vertex 1: bad number ','");
    CHECK(ply_error(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.0\n") == "face 0: bad integer '2.0'");
    CHECK(ply_error(head + "0 0 0\n1 0 0\n0 1 0\n3.0 0 1 2\n") == "face 0: bad integer '3.0'");
    CHECK(ply_error(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n") ==
          "face 0: bad integer '99999999999999999999'");
    // Not finite, or out of double's range: read, for collect_model to refuse.
    const RawModel m = read_ply(head + "nan 0 0\n1 inf 0\n-1e999 1e-999 -INF\n3 0 1 2\n");
    const RawMesh& mesh = m.meshes[0];
    CHECK(std::isnan(mesh.positions[0].x));
    CHECK(mesh.positions[1].y == std::numeric_limits<double>::infinity());
    CHECK(mesh.positions[2].x == -std::numeric_limits<double>::infinity());
    CHECK(mesh.positions[2].y == 0);
    CHECK(mesh.positions[2].z == -std::numeric_limits<double>::infinity());
    CHECK_THROWS_WITH_AS(collect_model(m, MeshTransform{}.to_matrix(), "PLY"),
                         doctest::Contains("vertex 0 is not finite"), ModelError);
}

TEST_CASE("read_ply: save_ply's file reads back as the mesh rounded to float") {
    TempDir dir;
    MeshData src;
    src.vertices = {{0.1, 0.2, 0.3}, {1e10, -1.0 / 3, 2}, {-5, 7.125, 1e-30}, {3.14159265358979, 0, -2.5}};
    src.indices = {0, 1, 2, 2, 1, 3, 3, 0, 2};
    const std::string path = (dir.path / "round.ply").string();
    save_ply(src, path);
    const std::string bytes = read_bytes(path);
    // The layout save_ply promises: the header, then 12 bytes a vertex, 13 a triangle.
    const std::string h = "ply\nformat binary_little_endian 1.0\ncomment written by octray\nelement vertex 4\n"
                          "property float x\nproperty float y\nproperty float z\nelement face 3\n"
                          "property list uchar int vertex_indices\nend_header\n";
    REQUIRE(bytes.substr(0, h.size()) == h);
    CHECK(bytes.size() == h.size() + 4 * 12 + 3 * 13);
    std::vector<Vec3d> rounded;
    // Through a volatile float: GCC 12.2's SLP vectorizer at -O2 drops the rounding of
    // push_back({double(float(v.x)), double(float(v.y)), double(float(v.z))}) on x and y.
    auto to_float = [](double d) {
        volatile float f = static_cast<float>(d);
        return static_cast<double>(f);
    };
    for (const Vec3d& v : src.vertices) rounded.push_back({to_float(v.x), to_float(v.y), to_float(v.z)});
    CHECK(rounded[0].x != src.vertices[0].x);  // the rounding is real
    check_mesh(read_ply(bytes), rounded, src.indices);

    // What save_ply refuses, it refuses before creating the file.
    MeshData bad = src;
    bad.vertices[2].y = 1e300;
    const std::string bad_path = (dir.path / "bad.ply").string();
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), doctest::Contains(": vertex 2 (-5, 1"), ModelError);
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), doctest::Contains("does not fit in float"), ModelError);
    bad = src;
    bad.indices[7] = 4;
    const std::string oor = "cannot write " + bad_path + ": index 4 out of range (4 vertices)";
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), oor.c_str(), ModelError);
    CHECK_FALSE(fs::exists(bad_path));
    CHECK_THROWS_WITH_AS(save_ply(src, (dir.path / "no" / "dir.ply").string()),
                         doctest::Contains("No such file or directory"), ModelError);
}

TEST_CASE("read_ply: assimp-testmodels' PLY files read or give a ModelError") {
    if (!have_models()) return;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(model("PLY")))
        if (e.is_regular_file() && e.path().extension() == ".ply") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    REQUIRE(!files.empty());
    std::size_t read = 0;
    for (const fs::path& p : files) {
        INFO("file: " << p.string());
        const std::string bytes = read_bytes(p.string());
        try {
            const RawModel m = read_ply(bytes);
            REQUIRE(m.meshes.size() == 1);
            MESSAGE(p.filename().string() << ": read, " << m.meshes[0].positions.size() << " vertices, "
                                          << m.meshes[0].triangles.size() / 3 << " triangles");
            ++read;
        } catch (const ModelError& e) {
            MESSAGE(p.filename().string() << ": ModelError: " << std::string(e.what()));
        }
    }
    CHECK(read > 0);
}
