// io/mesh_generators.cpp — see mesh_generators.hpp.
#include "mesh_generators.hpp"

#include <octray/constants.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace octray {

namespace {

void add_triangle(MeshData& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    m.indices.push_back(a);
    m.indices.push_back(b);
    m.indices.push_back(c);
}

}  // namespace

MeshData uv_sphere(int rings, int segments) {
    if (rings < 2 || segments < 3 || rings > 65536 || segments > 65536)
        throw std::invalid_argument("uv_sphere: need 2 <= rings <= 65536 and 3 <= segments <= 65536, got " +
                                    std::to_string(rings) + ", " + std::to_string(segments));
    MeshData m;
    m.format = "generated";
    const auto seg = static_cast<std::uint32_t>(segments);
    m.vertices.reserve(std::size_t(rings - 1) * seg + 2);
    m.vertices.push_back({0, 1, 0});
    for (int r = 1; r < rings; ++r) {
        const double theta = kPi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2 * kPi * s / segments;
            m.vertices.push_back({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
        }
    }
    m.vertices.push_back({0, -1, 0});
    const auto south = static_cast<std::uint32_t>(m.vertices.size() - 1);
    auto at = [seg](int r, std::uint32_t s) { return 1 + std::uint32_t(r - 1) * seg + s % seg; };

    m.indices.reserve(std::size_t(6) * seg * std::size_t(rings - 1));
    for (std::uint32_t s = 0; s < seg; ++s) add_triangle(m, 0, at(1, s + 1), at(1, s));
    for (int r = 1; r + 1 < rings; ++r)
        for (std::uint32_t s = 0; s < seg; ++s) {
            add_triangle(m, at(r, s), at(r, s + 1), at(r + 1, s));
            add_triangle(m, at(r + 1, s), at(r, s + 1), at(r + 1, s + 1));
        }
    for (std::uint32_t s = 0; s < seg; ++s) add_triangle(m, at(rings - 1, s), at(rings - 1, s + 1), south);
    return m;
}

MeshData height_field(int n) {
    if (n < 1 || n > 4096) throw std::invalid_argument("height_field: need 1 <= n <= 4096, got " + std::to_string(n));
    MeshData m;
    m.format = "generated";
    const auto side = static_cast<std::uint32_t>(n) + 1;
    m.vertices.reserve(std::size_t(side) * side);
    for (std::uint32_t j = 0; j < side; ++j)
        for (std::uint32_t i = 0; i < side; ++i) {
            const double x = -1 + 2.0 * i / n, z = -1 + 2.0 * j / n;
            m.vertices.push_back({x, 0.25 * std::sin(kPi * x) * std::cos(kPi * z), z});
        }
    m.indices.reserve(std::size_t(6) * n * n);
    for (std::uint32_t j = 0; j + 1 < side; ++j)
        for (std::uint32_t i = 0; i + 1 < side; ++i) {
            const std::uint32_t a = j * side + i, b = a + 1, c = a + side, d = c + 1;
            add_triangle(m, a, c, b);
            add_triangle(m, b, c, d);
        }
    return m;
}

}  // namespace octray
