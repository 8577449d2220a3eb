// io/ply_header.cpp — parse_header and check_counts (ply_header.hpp): the PLY header's
// lines, `ply`, `format`, `comment`/`obj_info`, `element NAME COUNT`, `property TYPE NAME`,
// `property list COUNT_TYPE ITEM_TYPE NAME` and `end_header`, each ending in \n or \r\n;
// a line of any other first word is passed over like a comment.
// Types: char/int8, uchar/uint8, short/int16, ushort/uint16, int/int32, uint/uint32,
// float/float32, double/float64.
#include "ply_header.hpp"

#include <charconv>
#include <cstdlib>
#include <system_error>

namespace octray::model_formats::ply {

namespace {

bool parse_type(std::string_view s, Type& t) {
    struct Name { std::string_view name; Type type; };
    static constexpr Name names[] = {
        {"char", Type::i8},   {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
        {"short", Type::i16}, {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
        {"int", Type::i32},   {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
        {"float", Type::f32}, {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
    for (const Name& n : names)
        if (n.name == s) {
            t = n.type;
            return true;
        }
    return false;
}

// A header line's first `most` words (one more when there are more), so that a long
// line costs no more than its scan.
std::vector<std::string_view> split(std::string_view line, std::size_t most = 5) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size() && out.size() <= most) {
        while (i < line.size() && is_space(line[i])) ++i;
        const std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) out.push_back(line.substr(start, i - start));
    }
    return out;
}

// from_chars takes no leading '+'; PLY writers may put one.
std::string_view drop_plus(std::string_view s) {
    return (s.size() > 1 && s[0] == '+' && s[1] != '+' && s[1] != '-') ? s.substr(1) : s;
}

bool parse_u64(std::string_view s, std::uint64_t& v) {
    s = drop_plus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size();
}

}  // namespace

std::string quote(std::string_view s) {
    std::string q(s.substr(0, 40));
    for (char& c : q)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
    if (s.size() > 40) q += "...";
    return "'" + q + "'";
}

bool parse_i64(std::string_view s, std::int64_t& v) {
    s = drop_plus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    return ec == std::errc() && end == s.data() + s.size();
}

bool parse_double(std::string_view s, double& v) {
    s = drop_plus(s);
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (end != s.data() + s.size()) return false;
    if (ec == std::errc()) return true;
    if (ec != std::errc::result_out_of_range || s.size() > 400) return false;
    // Out of double's range: strtod says what it is (±huge, or a subnormal or zero),
    // for collect_model to judge. The token is copied to end in a NUL.
    const std::string copy(s);
    v = std::strtod(copy.c_str(), nullptr);
    return true;
}

Header parse_header(std::string_view bytes) {
    Header h;
    bool have_format = false, have_vertex = false, have_face = false;
    std::size_t pos = 0;
    std::size_t line_no = 0;
    for (;;) {
        if (pos >= bytes.size())
            throw ModelError(line_no == 0 ? "not a ply file: no 'ply' line at the start" : "missing end_header");
        const std::size_t nl = bytes.find('\n', pos);
        std::string_view line = bytes.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? bytes.size() : nl + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        const std::vector<std::string_view> t = split(line);
        if (line_no == 1) {
            if (t.size() != 1 || t[0] != "ply") throw ModelError("not a ply file: no 'ply' line at the start");
            continue;
        }
        const std::string where = "header line " + std::to_string(line_no) + ": ";
        auto bad_line = [&]() { return ModelError("bad header line " + std::to_string(line_no) + ": " + quote(line)); };
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
        // Names are quoted raw in later messages: a control character (a NUL cuts what()
        // short) makes the line bad here (found by fuzz/ply_fuzz.cpp).
        for (const std::string_view token : t)
            for (const char c : token)
                if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) throw bad_line();
        if (t[0] == "end_header") {
            if (t.size() != 1) throw bad_line();
            break;
        }
        if (t[0] == "format") {
            if (t.size() != 3 || have_format) throw bad_line();
            if (t[1] == "ascii") h.encoding = Encoding::ascii;
            else if (t[1] == "binary_little_endian") h.encoding = Encoding::little;
            else if (t[1] == "binary_big_endian") h.encoding = Encoding::big;
            else throw ModelError(where + "unknown format " + quote(t[1]));
            if (t[2] != "1.0") throw ModelError(where + "unknown format version " + quote(t[2]));
            have_format = true;
        } else if (t[0] == "element") {
            if (t.size() != 3) throw bad_line();
            Element e;
            e.name = std::string(t[1]);
            if (!parse_u64(t[2], e.count)) throw ModelError(where + "bad element count " + quote(t[2]));
            if (e.name == "vertex" || e.name == "face") {
                bool& seen = e.name == "vertex" ? have_vertex : have_face;
                if (seen) throw ModelError(where + "a second element " + quote(e.name));
                seen = true;
            }
            h.elements.push_back(std::move(e));
        } else if (t[0] == "property") {
            if (h.elements.empty()) throw ModelError(where + "property before any element");
            Property p;
            if (t.size() == 3 && t[1] != "list") {
                if (!parse_type(t[1], p.type)) throw ModelError(where + "unknown type " + quote(t[1]));
                p.name = std::string(t[2]);
            } else if (t.size() == 5 && t[1] == "list") {
                if (!parse_type(t[2], p.count_type)) throw ModelError(where + "unknown type " + quote(t[2]));
                if (!parse_type(t[3], p.type)) throw ModelError(where + "unknown type " + quote(t[3]));
                if (!integral(p.count_type))
                    throw ModelError(where + "list count type " + quote(t[2]) + " is not an integer type");
                p.list = true;
                p.name = std::string(t[4]);
            } else {
                throw bad_line();
            }
            Element& e = h.elements.back();
            e.has_list = e.has_list || p.list;
            e.min_row_bytes += size_of(p.list ? p.count_type : p.type);
            e.props.push_back(std::move(p));
        }
        // Any other line is passed over as a comment: Blender 2.47's exporter wrote one
        // unmarked (assimp-testmodels' Wuson.ply).
    }
    if (!have_format) throw ModelError("missing format line");
    h.data_offset = pos;
    return h;
}

void check_counts(const Header& h, std::uint64_t bytes) {
    const bool ascii = h.encoding == Encoding::ascii;
    std::uint64_t total = 0;
    for (const Element& e : h.elements) {
        const std::uint64_t need =
            ascii ? mul_sat(mul_sat(e.count, e.props.size()), 2) : mul_sat(e.count, e.min_row_bytes);
        if (need > bytes + (ascii ? 1 : 0))
            throw ModelError(e.name + " count " + std::to_string(e.count) + " does not fit in the file's " +
                             std::to_string(bytes) + " bytes after the header");
        total = add_sat(total, need);
    }
    if (total > bytes + (ascii ? 1 : 0))
        throw ModelError("the element counts need at least " + std::to_string(total) + " bytes, the file has " +
                         std::to_string(bytes) + " after the header");
}

}  // namespace octray::model_formats::ply
