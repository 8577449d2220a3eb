// io/image_io.cpp — PNG via stb (libstb provides the implementations), PFM by hand.
#include "image_io.hpp"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

namespace octray {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
    throw std::runtime_error(path + ": " + problem);
}

[[noreturn]] void fail_errno(const std::string& path, const std::string& action, int err) {
    fail(path, action + ": " + std::strerror(err));
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr open_or_throw(const std::string& path, const char* mode, const char* action) {
    FilePtr f(std::fopen(path.c_str(), mode));
    if (!f) fail_errno(path, action, errno);
    return f;
}

// Writes through one FILE* so that both the open and the write/close errors
// report errno, which stbi_write_png alone would swallow.
class Writer {
public:
    explicit Writer(const std::string& path) : path_(path), file_(open_or_throw(path, "wb", "cannot open for writing")) {}

    void write(const void* data, std::size_t n) {
        if (ok_ && std::fwrite(data, 1, n, file_.get()) != n) {
            ok_ = false;
            err_ = errno;
        }
    }

    void close() {
        const bool closed = std::fclose(file_.release()) == 0;
        if (ok_ && !closed) {
            ok_ = false;
            err_ = errno;
        }
        if (!ok_) fail_errno(path_, "cannot write", err_);
    }

private:
    std::string path_;
    FilePtr file_;
    bool ok_ = true;
    int err_ = 0;
};

void check_size(const std::string& path, int width, int height, std::size_t values) {
    if (width <= 0 || height <= 0) fail(path, "cannot write an empty image");
    if (values != std::size_t(3) * std::size_t(width) * std::size_t(height))
        fail(path, "image buffer size does not match its width and height");
}

// float32 bytes in little-endian order regardless of the host's byte order.
void put_le(float f, unsigned char* out) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    for (int k = 0; k < 4; ++k) out[k] = static_cast<unsigned char>(bits >> (8 * k));
}

template <class T>
void write_pfm_any(const std::string& path, const Image<T>& image) {
    check_size(path, image.width, image.height, image.rgb.size());
    Writer out(path);
    const std::string header = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
    out.write(header.data(), header.size());
    std::vector<unsigned char> row(std::size_t(12) * std::size_t(image.width));
    for (int j = image.height - 1; j >= 0; --j) {  // PFM stores the bottom row first
        const T* src = image.pixel(0, j);
        for (std::size_t k = 0; k < std::size_t(3) * std::size_t(image.width); ++k) put_le(static_cast<float>(src[k]), &row[4 * k]);
        out.write(row.data(), row.size());
    }
    out.close();
}

std::string read_all(const std::string& path) {
    FilePtr f = open_or_throw(path, "rb", "cannot open");
    std::string data;
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f.get())) > 0) data.append(buf, n);
    if (std::ferror(f.get())) fail_errno(path, "cannot read", errno);
    return data;
}

}  // namespace

void write_png(const std::string& path, const ImageRGB8& image) {
    check_size(path, image.width, image.height, image.rgb.size());
    Writer out(path);
    auto sink = [](void* context, void* data, int size) {
        static_cast<Writer*>(context)->write(data, static_cast<std::size_t>(size));
    };
    if (!stbi_write_png_to_func(sink, &out, image.width, image.height, 3, image.rgb.data(), 3 * image.width))
        fail(path, "cannot encode PNG");
    out.close();
}

ImageRGB8 read_png(const std::string& path) {
    FilePtr f = open_or_throw(path, "rb", "cannot open");
    int w = 0, h = 0, channels = 0;
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(stbi_load_from_file(f.get(), &w, &h, &channels, 3), stbi_image_free);
    if (!pixels) fail(path, std::string("cannot decode PNG: ") + stbi_failure_reason());
    ImageRGB8 image(w, h);
    std::memcpy(image.rgb.data(), pixels.get(), image.rgb.size());
    return image;
}

void write_pfm(const std::string& path, const Image<float>& image) { write_pfm_any(path, image); }
void write_pfm(const std::string& path, const Image<double>& image) { write_pfm_any(path, image); }

Image<float> read_pfm(const std::string& path) {
    const std::string data = read_all(path);
    // Header: "PF", whitespace, width, whitespace, height, whitespace, scale,
    // then exactly one whitespace character before the binary data.
    std::size_t pos = 0;
    auto skip_space = [&] {
        while (pos < data.size() && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
    };
    auto token = [&] {
        skip_space();
        const std::size_t start = pos;
        while (pos < data.size() && !std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
        return data.substr(start, pos - start);
    };
    if (token() != "PF") fail(path, "not a colour PFM file (expected \"PF\")");
    const std::string ws = token(), hs = token(), ss = token();
    char* end = nullptr;
    const long w = std::strtol(ws.c_str(), &end, 10);
    const bool w_ok = !ws.empty() && *end == '\0';
    const long h = std::strtol(hs.c_str(), &end, 10);
    const bool h_ok = !hs.empty() && *end == '\0';
    const double scale = std::strtod(ss.c_str(), &end);
    const bool s_ok = !ss.empty() && *end == '\0' && scale != 0 && std::isfinite(scale);
    constexpr long kMaxSide = 1 << 20;
    if (!w_ok || !h_ok || !s_ok || w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide || pos >= data.size())
        fail(path, "malformed PFM header");
    ++pos;  // the single whitespace character ending the header

    Image<float> image(static_cast<int>(w), static_cast<int>(h));
    if (data.size() - pos < 4 * image.rgb.size()) fail(path, "PFM data is truncated");
    const bool little = scale < 0;  // the sign of the scale gives the byte order
    const std::size_t row_values = std::size_t(3) * std::size_t(w);
    for (long j = 0; j < h; ++j) {
        float* dst = image.pixel(0, static_cast<int>(h - 1 - j));  // file row 0 is the bottom row
        for (std::size_t k = 0; k < row_values; ++k) {
            const auto* b = reinterpret_cast<const unsigned char*>(data.data() + pos + 4 * (std::size_t(j) * row_values + k));
            std::uint32_t bits = 0;
            for (int i = 0; i < 4; ++i) bits |= std::uint32_t(b[little ? i : 3 - i]) << (8 * i);
            std::memcpy(&dst[k], &bits, 4);
        }
    }
    return image;
}

}  // namespace octray
