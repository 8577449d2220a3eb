// io/obj_reader.cpp — read_obj (model_formats.hpp): Wavefront OBJ (the "Object Files
// (.obj)" appendix B1 of the Advanced Visualizer manual) with tinyobjloader 2.0.0rc10,
// Debian's libtinyobjloader-dev, compiled here from its header (its .so is not linked),
// so the sanitizer and fuzz builds see into it.
//
// Read: "v" positions, "f" faces (v, v/vt, v//vn, v/vt/vn; negative indices relative to
// the vertices so far), "g" and "o" as mesh boundaries (one RawMesh per tinyobj shape,
// named as tinyobj names it). Faces are fanned here (v0, vi, vi+1) as PLY's are;
// faces of fewer than 3 vertices are skipped.
// Left out: points "p", lines "l", normals, texture coordinates, materials ("mtllib" is
// never opened: an untrusted file could name any path; "usemtl" is ignored), everything
// else. tinyobj is shown those lines as comments (ObjBytes below), so none of its code
// for them runs on untrusted input.
// Refused (ModelError): a vertex index 0, beyond the vertex count, or negative beyond the
// vertices so far ("face 7 (line 12): index -12 out of range (8 vertices)"); a "v" line
// with fewer than 3 coordinates or one tinyobj reads no number from; numbers tinyobj cannot
// parse safely (see prescan); more than kMaxModelTriangles triangles after fanning.
//
// Why a prescan before tinyobj: its parser has undefined behaviour on some input, and
// reads other input wrongly without a word:
// - indices are read with atoi, undefined when the value does not fit an int (glibc
//   returns (int)LONG_MAX, i.e. -1, so "f 99999999999999999999 1 2" used the last vertex);
// - tryParseDouble's exponent check lets "1e2147483648" overflow an int, and counts a
//   number's digits in an int;
// - "nan" and "inf" are not numbers to it: it stores 0 (here they are passed through,
//   and collect_model refuses them), as it does for a missing coordinate;
// - with triangulate=false a face's vertex count is kept in an unsigned char (a face of
//   300 vertices says 44): the prescan keeps the real counts.
// The prescan mirrors tinyobj's line splitting and index parsing; what it finds wrong is
// refused before tinyobj runs.
//
// real_t is double (TINYOBJLOADER_USE_DOUBLE): tinyobj's parser computes in double
// anyway, positions are Vec3d and the transform is applied in double; float would round
// "0.1" to 0.100000001490116 before the transform.
#include "model_formats.hpp"

#define TINYOBJLOADER_IMPLEMENTATION
#define TINYOBJLOADER_USE_DOUBLE
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <istream>
#include <limits>
#include <new>
#include <streambuf>

namespace octray::model_formats {

namespace {

// tinyobj's line: up to '\n', '\r' or "\r\n" (its safeGetline); its C-string functions
// then stop at the first NUL.
struct Line {
    std::string_view text;  // to the first NUL, without the terminator
    std::size_t next;       // where the next line starts
};

Line line_at(std::string_view bytes, std::size_t at) {
    std::size_t end = at;
    while (end < bytes.size() && bytes[end] != '\n' && bytes[end] != '\r') ++end;
    std::size_t next = end;
    if (next < bytes.size()) next += (bytes[next] == '\r' && next + 1 < bytes.size() && bytes[next + 1] == '\n') ? 2 : 1;
    std::string_view text = bytes.substr(at, end - at);
    if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) text = text.substr(0, nul);
    return {text, next};
}

bool is_space(char c) { return c == ' ' || c == '\t'; }

// The line's keyword as tinyobj sees it: 'v', 'f', 'g' or 'o' followed by a space or tab;
// 0 for anything else.
char kind_of(std::string_view text) {
    std::size_t i = 0;
    while (i < text.size() && is_space(text[i])) ++i;
    if (i + 1 >= text.size() || !is_space(text[i + 1])) return 0;
    const char c = text[i];
    return (c == 'v' || c == 'f' || c == 'g' || c == 'o') ? c : 0;
}

// The file's bytes as tinyobj reads them, not copied: every line that is not v, f, g or
// o is given a leading '#', so tinyobj takes it for a comment.
class ObjBytes final : public std::streambuf {
public:
    explicit ObjBytes(std::string_view bytes) : bytes_(bytes) {}

protected:
    int_type underflow() override {
        if (at_ >= bytes_.size()) return traits_type::eof();
        if (line_start_) {
            line_start_ = false;
            const Line line = line_at(bytes_, at_);
            if (kind_of(line.text) == 0 && !line.text.empty()) {
                setg(hash_, hash_, hash_ + 1);
                return traits_type::to_int_type('#');
            }
        }
        const std::size_t next = line_at(bytes_, at_).next;
        char* begin = const_cast<char*>(bytes_.data() + at_);  // only read: no putback area
        setg(begin, begin, begin + (next - at_));
        at_ = next;
        line_start_ = true;
        return traits_type::to_int_type(*begin);
    }

private:
    std::string_view bytes_;
    std::size_t at_ = 0;
    bool line_start_ = true;
    char hash_[1] = {'#'};
};

// mtllib: nothing is read, whatever the file names.
class NoMaterials final : public tinyobj::MaterialReader {
public:
    bool operator()(const std::string&, std::vector<tinyobj::material_t>*, std::map<std::string, int>*,
                    std::string*, std::string*) override {
        return false;
    }
};

// A tinyobj token: from after " \t" to the next " \t" (its strspn/strcspn).
std::string_view next_token(std::string_view text, std::size_t& at) {
    while (at < text.size() && is_space(text[at])) ++at;
    const std::size_t start = at;
    while (at < text.size() && !is_space(text[at])) ++at;
    return text.substr(start, at - start);
}

constexpr std::size_t kMaxNumberChars = 1024;  // tinyobj counts digits in an int
constexpr int kMaxExponentDigits = 9;          // significant digits tinyobj's int holds safely

// The number tokens tinyobj reads on a "v" line are safe for tryParseDouble: not too long,
// no exponent of more than kMaxExponentDigits significant digits.
bool safe_for_tinyobj(std::string_view tok) {
    if (tok.size() > kMaxNumberChars) return false;
    for (std::size_t i = 0; i < tok.size(); ++i) {
        if (tok[i] != 'e' && tok[i] != 'E') continue;
        std::size_t j = i + 1;
        if (j < tok.size() && (tok[j] == '+' || tok[j] == '-')) ++j;
        while (j < tok.size() && tok[j] == '0') ++j;
        int digits = 0;
        while (j < tok.size() && std::isdigit(static_cast<unsigned char>(tok[j]))) ++j, ++digits;
        if (digits > kMaxExponentDigits) return false;
    }
    return true;
}

// Whether tinyobj's tryParseDouble reads a number at the start of the token (it stops at
// the first character that does not fit: "3.1+e2" is 3.1, as assimp reads it too). Where
// it does not ("abc", "1ex", "-"), tinyobj stores 0 without a word: refused instead.
bool tinyobj_reads(std::string_view t) {
    std::size_t i = 0;
    auto digit = [&](std::size_t k) { return k < t.size() && std::isdigit(static_cast<unsigned char>(t[k])); };
    auto digits = [&] {
        const std::size_t s = i;
        while (digit(i)) ++i;
        return i - s;
    };
    bool leading_dot = false;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) {
        ++i;
        leading_dot = i < t.size() && t[i] == '.';
    } else if (i < t.size() && t[i] == '.') {
        leading_dot = true;
    } else if (!digit(i)) {
        return false;
    }
    if (!leading_dot && digits() == 0) return false;
    if (i == t.size()) return true;
    if (t[i] == '.') {
        ++i;
        digits();
    } else if (t[i] != 'e' && t[i] != 'E') {
        return true;
    }
    if (i == t.size() || (t[i] != 'e' && t[i] != 'E')) return true;
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    else if (!digit(i)) return false;
    return digits() > 0;
}

// nan or inf[inity], any case, signed or not: tinyobj stores 0 for these; the value is put
// back after it has read the file.
bool non_finite_literal(std::string_view t, double& value) {
    std::string s(t);
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string_view u = s;
    const bool negative = !u.empty() && u[0] == '-';
    if (!u.empty() && (u[0] == '-' || u[0] == '+')) u.remove_prefix(1);
    if (u == "nan") value = std::numeric_limits<double>::quiet_NaN();
    else if (u == "inf" || u == "infinity") value = std::numeric_limits<double>::infinity();
    else return false;
    if (negative) value = -value;
    return true;
}

// atoi as glibc reads a field (leading isspace, sign, digits), without its undefined
// behaviour: `fits` is false when the value is outside int. `written` is the sign and
// digits as they stand in the file.
struct Field {
    long long value = 0;
    bool fits = true;
    std::string_view written;
    std::size_t digits = 0;
    std::string_view rest;  // the field and what follows it on the line
};

Field read_field(std::string_view text, std::size_t at) {
    Field f;
    while (at < text.size() && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
    f.rest = text.substr(at);
    const std::size_t start = at;
    bool negative = false;
    if (at < text.size() && (text[at] == '+' || text[at] == '-')) negative = text[at++] == '-';
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at]))) {
        if (f.fits) {
            f.value = f.value * 10 + (text[at] - '0');
            if (f.value > static_cast<long long>(INT_MAX) + 1) f.fits = false;
        }
        ++at;
        ++f.digits;
    }
    if (negative) f.value = -f.value;
    if (f.value > INT_MAX || f.value < INT_MIN) f.fits = false;
    f.written = text.substr(start, at - start);
    return f;
}

// tinyobj's strcspn(token, "/ \t\r").
std::size_t skip_field(std::string_view text, std::size_t at) {
    while (at < text.size() && text[at] != '/' && !is_space(text[at])) ++at;
    return at;
}

struct Override {
    std::size_t vertex;
    unsigned coord;
    double value;
};

struct Prescan {
    std::vector<std::uint32_t> face_sizes;  // faces of 3 or more vertices, in file order
    std::vector<Override> overrides;        // nan and inf coordinates
};

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

// The vertex field of one face corner: in range, as tinyobj will resolve it.
void check_vertex_index(const Field& f, std::size_t face, std::size_t line, long long so_far, long long total) {
    const bool ok = f.fits && f.value != 0 && (f.value > 0 ? f.value <= total : -f.value <= so_far);
    if (ok) return;
    if (f.digits == 0)  // atoi reads 0, which tinyobj refuses: "f 1 2 3 # comment" too
        throw ModelError("face " + std::to_string(face) + " (line " + std::to_string(line) + "): '" +
                         std::string(f.rest.substr(0, 20)) + "' is not an index");
    const std::string written = f.written.empty() ? std::string("0") : std::string(f.written.substr(0, 40));
    const bool relative = !f.written.empty() && f.written[0] == '-';  // counts the vertices so far
    throw ModelError("face " + std::to_string(face) + " (line " + std::to_string(line) + "): index " + written +
                     " out of range (" + std::to_string(relative ? so_far : total) + " vertices)");
}

// What the file comment says, line by line as tinyobj will read them.
Prescan prescan(std::string_view bytes) {
    long long total = 0;
    for (std::size_t at = 0; at < bytes.size();) {
        const Line line = line_at(bytes, at);
        if (kind_of(line.text) == 'v') ++total;
        at = line.next;
    }
    if (total > INT_MAX) throw ModelError("too many vertices: " + std::to_string(total));

    Prescan out;
    long long vertices = 0;
    std::size_t faces = 0, line_number = 0;
    std::uint64_t triangles = 0;
    for (std::size_t at = 0; at < bytes.size();) {
        const Line line = line_at(bytes, at);
        at = line.next;
        ++line_number;
        const std::string_view text = line.text;
        const char kind = kind_of(text);
        if (kind != 'v' && kind != 'f') continue;
        std::size_t i = text.find_first_not_of(" \t") + 2;  // past the keyword and its space
        if (kind == 'v') {
            for (unsigned c = 0; c < 6; ++c) {  // x y z, then tinyobj's w or r g b
                const std::string_view tok = next_token(text, i);
                if (c >= 3 && tok.empty()) break;
                if (c < 3) {
                    double value = 0;
                    if (tok.empty()) throw ModelError(at_line(line_number) + "'v' needs 3 coordinates");
                    if (non_finite_literal(tok, value)) {
                        out.overrides.push_back({static_cast<std::size_t>(vertices), c, value});
                        continue;
                    }
                    if (!tinyobj_reads(tok))
                        throw ModelError(at_line(line_number) + "coordinate '" + std::string(tok.substr(0, 40)) +
                                         "' is not a number");
                }
                if (!safe_for_tinyobj(tok))
                    throw ModelError(at_line(line_number) + "number '" + std::string(tok.substr(0, 40)) +
                                     "' too long or its exponent too large");
            }
            ++vertices;
        } else if (kind == 'f') {
            ++faces;
            std::uint64_t corners = 0;
            while (i < text.size() && is_space(text[i])) ++i;
            // tinyobj's face loop and parseTriple, field by field.
            while (i < text.size() && text[i] != '\r') {
                const Field v = read_field(text, i);
                check_vertex_index(v, faces, line_number, vertices, total);
                i = skip_field(text, i);
                if (i < text.size() && text[i] == '/') {
                    ++i;
                    const bool vn_only = i < text.size() && text[i] == '/';
                    if (vn_only) ++i;
                    for (int k = vn_only ? 1 : 0; k < 2; ++k) {  // vt then vn, or vn
                        const Field t = read_field(text, i);
                        if (!t.fits)
                            throw ModelError("face " + std::to_string(faces) + " (line " + std::to_string(line_number) +
                                             "): index " + std::string(t.written.substr(0, 40)) + " out of range");
                        i = skip_field(text, i);
                        if (k == 0 && !(i < text.size() && text[i] == '/')) break;
                        if (k == 0) ++i;
                    }
                }
                ++corners;
                while (i < text.size() && (is_space(text[i]) || text[i] == '\r')) ++i;
            }
            if (corners >= 3) {
                if (corners > UINT32_MAX) throw ModelError("face " + std::to_string(faces) + ": too many vertices");
                out.face_sizes.push_back(static_cast<std::uint32_t>(corners));
                triangles += corners - 2;
                if (triangles > kMaxModelTriangles)
                    throw ModelError("too many triangles: more than " + std::to_string(kMaxModelTriangles) +
                                     " (the limit)");
            }
        }
    }
    return out;
}

// The first line of tinyobj's message, lower-cased at its start.
std::string first_line(const std::string& s) {
    std::string line = s.substr(0, s.find('\n'));
    if (!line.empty()) line[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(line[0])));
    return line;
}

[[noreturn]] void broken(const std::string& why) {
    throw ModelError("unreadable OBJ: " + why + " (the reader's prescan and tinyobjloader disagree)");
}

}  // namespace

RawModel read_obj(std::string_view bytes) {
    try {
        const Prescan pre = prescan(bytes);

        tinyobj::attrib_t attrib;
        std::vector<tinyobj::shape_t> shapes;
        std::vector<tinyobj::material_t> materials;
        std::string warn, err;
        ObjBytes buffer(bytes);
        std::istream in(&buffer);
        NoMaterials no_materials;
        if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, &no_materials,
                              /*triangulate=*/false, /*default_vcols_fallback=*/false))
            throw ModelError("unreadable OBJ: " + first_line(err));
        if (!err.empty()) throw ModelError("unreadable OBJ: " + first_line(err));
        // Its index warnings ("Vertex indices out of bounds") are errors; the prescan has
        // already refused what they would say about vertices. Normals and texture
        // coordinates are not used: their warnings are not.
        for (std::size_t at = 0; at < warn.size();) {
            const std::size_t end = std::min(warn.find('\n', at), warn.size());
            const std::string w = warn.substr(at, end - at);
            if (w.rfind("Vertex indices", 0) == 0 || w.find("invalid vertex index") != std::string::npos)
                throw ModelError("unreadable OBJ: " + first_line(w));
            at = end + 1;
        }

        const std::vector<double>& xyz = attrib.vertices;
        const std::size_t count = xyz.size() / 3;
        std::vector<double> fixed;  // xyz with the prescan's nan and inf put back
        if (!pre.overrides.empty()) {
            fixed = xyz;
            for (const Override& o : pre.overrides) {
                if (o.vertex >= count) broken("vertex count");
                fixed[3 * o.vertex + o.coord] = o.value;
            }
        }
        const std::vector<double>& pos = pre.overrides.empty() ? xyz : fixed;

        RawModel model;
        // Each shape's vertices renumbered in first use: memory follows what is used.
        std::vector<std::uint32_t> local(count), stamp(count, 0);
        std::size_t face = 0;
        for (std::size_t s = 0; s < shapes.size(); ++s) {
            const tinyobj::mesh_t& mesh = shapes[s].mesh;
            RawMesh out;
            out.name = shapes[s].name;
            const auto mark = static_cast<std::uint32_t>(s + 1);
            std::size_t at = 0;
            for (const unsigned char said : mesh.num_face_vertices) {
                if (face >= pre.face_sizes.size()) broken("face count");
                const std::uint32_t n = pre.face_sizes[face++];
                if ((n & 0xFF) != said || n > mesh.indices.size() - at) broken("face size");
                std::uint32_t corner[3];
                for (std::uint32_t k = 0; k < n; ++k) {
                    const int v = mesh.indices[at + k].vertex_index;
                    if (v < 0 || static_cast<std::size_t>(v) >= count) broken("index");
                    if (stamp[v] != mark) {
                        stamp[v] = mark;
                        local[v] = static_cast<std::uint32_t>(out.positions.size());
                        out.positions.push_back(
                            Vec3d{pos[3 * std::size_t(v)], pos[3 * std::size_t(v) + 1], pos[3 * std::size_t(v) + 2]});
                    }
                    const std::uint32_t l = local[v];
                    if (k == 0) corner[0] = l;  // fan: (v0, vi, vi+1)
                    else if (k == 1) corner[1] = l;
                    else {
                        corner[2] = l;
                        out.triangles.insert(out.triangles.end(), corner, corner + 3);
                        corner[1] = l;
                    }
                }
                at += n;
            }
            if (at != mesh.indices.size()) broken("index count");
            if (!out.triangles.empty()) model.meshes.push_back(std::move(out));
        }
        if (face != pre.face_sizes.size()) broken("face count");
        model.instance_each_mesh();
        return model;
    } catch (...) {
        rethrow_as_model_error("OBJ");
    }
}

}  // namespace octray::model_formats
