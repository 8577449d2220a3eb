// io/ply_header.hpp — the header half of octray's PLY reader (io/ply_reader.cpp reads the
// data): the header's elements and properties, and the checks made on them before any
// data is read. The format is Greg Turk's, "The PLY Polygon File Format" (1994).
#pragma once

#include "model_formats.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace octray::model_formats::ply {

enum class Type : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };
enum class Encoding { ascii, little, big };

constexpr std::size_t size_of(Type t) {
    switch (t) {
        case Type::i8: case Type::u8: return 1;
        case Type::i16: case Type::u16: return 2;
        case Type::i32: case Type::u32: case Type::f32: return 4;
        case Type::f64: return 8;
    }
    return 1;
}
constexpr bool integral(Type t) { return t != Type::f32 && t != Type::f64; }

struct Property {
    std::string name;
    Type type = Type::u8;        // a scalar's type, or a list's item type
    bool list = false;
    Type count_type = Type::u8;  // a list's count type (integral)
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> props;
    bool has_list = false;
    std::size_t min_row_bytes = 0;  // binary: scalars plus list counts (lists empty)
};

struct Header {
    Encoding encoding = Encoding::ascii;
    std::vector<Element> elements;
    std::size_t data_offset = 0;
};

// Counts are uint64 with saturating products, so no count overflows.
constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();
inline std::uint64_t mul_sat(std::uint64_t a, std::uint64_t b) {
    return (b != 0 && a > kSaturated / b) ? kSaturated : a * b;
}
inline std::uint64_t add_sat(std::uint64_t a, std::uint64_t b) { return a > kSaturated - b ? kSaturated : a + b; }

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

// A header line or token as a message may quote it: at most 40 characters, control
// characters shown as '?', so the message stays one short line.
std::string quote(std::string_view s);

// A whole token as a number (a leading '+' allowed); false when it is not one.
bool parse_i64(std::string_view s, std::int64_t& v);
// Out of double's range gives what strtod gives (±huge, a subnormal or zero).
bool parse_double(std::string_view s, double& v);

// The header, from the file's first byte to `end_header`; throws ModelError naming the line.
Header parse_header(std::string_view bytes);

// Each element's count, then all of them together, against the bytes after the header:
// a binary element needs at least count * (its smallest row) bytes, lists counted empty;
// an ASCII value at least two bytes (a character and a separator, bar the file's last).
void check_counts(const Header& h, std::uint64_t bytes);

}  // namespace octray::model_formats::ply
