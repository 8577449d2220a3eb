// tests/support/ply_files.hpp — PLY files for the read_ply tests (test_model_ply.cpp,
// test_model_ply_hostile.cpp), made by a small writer of the tests' own (make_ply). It
// lays out every binary value byte by byte with shifts in the named byte order, so the
// reader's loads are checked against an encoding they do not share. Expected meshes are
// written out by hand from the faces, fanned (v0, vi, vi+1).
#pragma once

#include "model_fixtures.hpp"
#include "model_formats.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace ply_files {

using namespace octray;
using namespace octray::model_formats;

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

inline std::size_t type_bytes(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "double" || t == "float64") return 8;
    return 4;
}

inline void put(std::string& out, const std::string& type, double v, Enc enc) {
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

inline std::string header(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
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

inline std::string body(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
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

inline std::string make_ply(const std::vector<Elem>& elems, Enc enc, const std::string& eol = "\n") {
    return header(elems, enc, eol) + body(elems, enc, eol);
}

// The small mesh every encoding writes: positions exact in float; a quad, a triangle, a
// two-index face and an empty one (both left out), a pentagon.
inline const std::vector<Vec3d> kPositions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 2.25, -1.5}};
inline const std::vector<std::vector<double>> kFaces = {{0, 1, 2, 3}, {1, 4, 2}, {3, 0}, {}, {0, 1, 4, 2, 3}};
inline const std::vector<std::uint32_t> kTriangles = {0, 1, 2, 0, 2, 3,  // quad
                                               1, 4, 2,           // triangle
                                               0, 1, 4, 0, 4, 2, 0, 2, 3};  // pentagon

inline Elem vertices(const std::string& type = "float") {
    Elem e{"vertex", {{type, "x", ""}, {type, "y", ""}, {type, "z", ""}}, {}};
    for (const Vec3d& p : kPositions) e.rows.push_back({{p.x}, {p.y}, {p.z}});
    return e;
}

inline Elem faces(const std::string& count_type = "uchar", const std::string& index_type = "int",
           const std::string& name = "vertex_indices") {
    Elem e{"face", {{index_type, name, count_type}}, {}};
    for (const auto& f : kFaces) e.rows.push_back({f});
    return e;
}

// One mesh, one identity instance, these positions exactly and these triangles.
inline void check_mesh(const RawModel& m, const std::vector<Vec3d>& positions, const std::vector<std::uint32_t>& triangles) {
    REQUIRE(m.meshes.size() == 1);
    REQUIRE(m.instances.size() == 1);
    CHECK(m.instances[0].mesh == 0);
    CHECK(m.meshes[0].name.empty());
    const RawMesh& mesh = m.meshes[0];
    model_fixtures::check_positions(mesh.positions, positions);
    CHECK(mesh.triangles == triangles);
}

inline void check_small_mesh(const RawModel& m) { check_mesh(m, kPositions, kTriangles); }

// read_ply's ModelError message, or "" when it reads.
inline std::string ply_error(const std::string& bytes) { return model_fixtures::read_error(read_ply, bytes); }

inline const Enc kEncodings[] = {Enc::ascii, Enc::le, Enc::be};
inline const char* enc_name(Enc e) { return e == Enc::ascii ? "ascii" : e == Enc::le ? "little-endian" : "big-endian"; }

}  // namespace ply_files
