// octray/image.hpp — a plain interleaved RGB image (row 0 is the top row).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace octray {

template <class T>
struct Image {
    int width = 0;
    int height = 0;
    std::vector<T> rgb;  // 3 * width * height, interleaved, rows top to bottom

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(std::size_t(3) * std::size_t(w) * std::size_t(h), T{}) {}
    T* pixel(int i, int j) { return rgb.data() + 3 * (std::size_t(j) * std::size_t(width) + std::size_t(i)); }
    const T* pixel(int i, int j) const { return rgb.data() + 3 * (std::size_t(j) * std::size_t(width) + std::size_t(i)); }
};

using ImageRGB8 = Image<std::uint8_t>;

}  // namespace octray
