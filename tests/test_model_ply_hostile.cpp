// tests/test_model_ply_hostile.cpp — the PLY files read_ply must refuse, each with a
// one-line ModelError naming where: counts the file cannot hold (refused before anything
// is allocated), the triangle limit, data cut short, indices out of range, broken headers
// and numbers. The files come from tests/support/ply_files.hpp.
#include "ply_files.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::model_formats;
using namespace ply_files;

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
