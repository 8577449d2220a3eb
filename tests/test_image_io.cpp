// PNG and PFM files: exact round trips, the PFM header and its bottom-to-top
// row order checked on the raw bytes, and error messages naming file and reason.
#include "image_io.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace {

// CTest may run test cases in parallel: one file name per test and process.
std::string temp_file(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("octray_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

float le_float(const std::string& bytes, std::size_t offset) {
    std::uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits |= std::uint32_t(static_cast<unsigned char>(bytes[offset + k])) << (8 * k);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

// Every value distinct, so a swapped row or channel cannot go unnoticed.
octray::Image<float> float_pattern(int w, int h) {
    octray::Image<float> img(w, h);
    for (std::size_t k = 0; k < img.rgb.size(); ++k) img.rgb[k] = 0.25f * float(k) - 1.5f;
    return img;
}

std::string error_of(void (*action)(const std::string&), const std::string& path) {
    try {
        action(path);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    FAIL("no error for " << path);
    return {};
}

}  // namespace

TEST_CASE("PNG round trip is exact") {
    octray::ImageRGB8 img(7, 5);
    for (std::size_t k = 0; k < img.rgb.size(); ++k) img.rgb[k] = static_cast<std::uint8_t>((k * 37 + 11) % 256);
    const std::string path = temp_file("roundtrip.png");
    octray::write_png(path, img);
    const octray::ImageRGB8 back = octray::read_png(path);
    CHECK(back.width == 7);
    CHECK(back.height == 5);
    CHECK(back.rgb == img.rgb);
    // It really is a PNG file.
    CHECK(read_bytes(path).substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
    std::filesystem::remove(path);
}

TEST_CASE("PFM round trip is bit-for-bit, including special values") {
    octray::Image<float> img = float_pattern(3, 2);
    img.rgb[0] = std::numeric_limits<float>::denorm_min();
    img.rgb[1] = -0.0f;
    img.rgb[2] = std::numeric_limits<float>::infinity();
    img.rgb[3] = std::numeric_limits<float>::max();
    const std::string path = temp_file("roundtrip.pfm");
    octray::write_pfm(path, img);
    const octray::Image<float> back = octray::read_pfm(path);
    REQUIRE(back.width == 3);
    REQUIRE(back.height == 2);
    REQUIRE(back.rgb.size() == img.rgb.size());
    CHECK(std::memcmp(back.rgb.data(), img.rgb.data(), img.rgb.size() * sizeof(float)) == 0);
    std::filesystem::remove(path);
}

TEST_CASE("PFM header bytes and bottom-to-top row order") {
    const octray::Image<float> img = float_pattern(4, 3);
    const std::string path = temp_file("layout.pfm");
    octray::write_pfm(path, img);
    const std::string bytes = read_bytes(path);
    const std::string header = "PF\n4 3\n-1.0\n";
    REQUIRE(bytes.size() == header.size() + 4 * 3 * 3 * 4);
    CHECK(bytes.substr(0, header.size()) == header);
    // File row r holds image row height-1-r: the first data row is the bottom one.
    for (int r = 0; r < 3; ++r) {
        const float* expected = img.pixel(0, 2 - r);
        for (int k = 0; k < 12; ++k) CHECK(le_float(bytes, header.size() + 4 * (12 * r + k)) == expected[k]);
    }
    std::filesystem::remove(path);
}

TEST_CASE("PFM from a double image stores the nearest floats") {
    octray::Image<double> img(2, 2);
    for (std::size_t k = 0; k < img.rgb.size(); ++k) img.rgb[k] = 0.1 * double(k) + 1e-3;
    const std::string path = temp_file("double.pfm");
    octray::write_pfm(path, img);
    const octray::Image<float> back = octray::read_pfm(path);
    REQUIRE(back.rgb.size() == img.rgb.size());
    for (std::size_t k = 0; k < img.rgb.size(); ++k) CHECK(back.rgb[k] == static_cast<float>(img.rgb[k]));
    std::filesystem::remove(path);
}

TEST_CASE("read_pfm honours a big-endian file (positive scale)") {
    const std::string path = temp_file("bigendian.pfm");
    {
        std::ofstream out(path, std::ios::binary);
        out << "PF\n1 2\n1.0\n";
        // Bottom row (1, 2, 3), then top row (4, 5, 6), each float big-endian.
        for (float f : {1.f, 2.f, 3.f, 4.f, 5.f, 6.f}) {
            std::uint32_t bits;
            std::memcpy(&bits, &f, 4);
            for (int k = 3; k >= 0; --k) out.put(static_cast<char>(bits >> (8 * k)));
        }
    }
    const octray::Image<float> img = octray::read_pfm(path);
    REQUIRE(img.width == 1);
    REQUIRE(img.height == 2);
    CHECK(img.pixel(0, 0)[0] == 4.f);
    CHECK(img.pixel(0, 0)[2] == 6.f);
    CHECK(img.pixel(0, 1)[0] == 1.f);
    std::filesystem::remove(path);
}

TEST_CASE("I/O errors name the file and the OS reason") {
    const std::string missing_dir = temp_file("no-such-dir") + "/x";
    const std::string png_msg =
        error_of([](const std::string& p) { octray::write_png(p, octray::ImageRGB8(1, 1)); }, missing_dir + ".png");
    CHECK(png_msg.find(missing_dir + ".png") != std::string::npos);
    CHECK(png_msg.find("No such file or directory") != std::string::npos);

    const std::string pfm_msg =
        error_of([](const std::string& p) { octray::write_pfm(p, octray::Image<float>(1, 1)); }, missing_dir + ".pfm");
    CHECK(pfm_msg.find(missing_dir + ".pfm") != std::string::npos);
    CHECK(pfm_msg.find("No such file or directory") != std::string::npos);

    const std::string read_msg = error_of([](const std::string& p) { octray::read_png(p); }, missing_dir + ".png");
    CHECK(read_msg.find("cannot open: No such file or directory") != std::string::npos);
    CHECK(error_of([](const std::string& p) { octray::read_pfm(p); }, missing_dir + ".pfm").find("No such file or directory") !=
          std::string::npos);
}

TEST_CASE("malformed PFM files are rejected") {
    const std::string path = temp_file("bad.pfm");
    auto write = [&](const std::string& content) { std::ofstream(path, std::ios::binary) << content; };

    write("P6\n1 1\n255\nabc");
    CHECK(error_of([](const std::string& p) { octray::read_pfm(p); }, path).find("not a colour PFM") != std::string::npos);
    write("PF\n2 x\n-1.0\n");
    CHECK(error_of([](const std::string& p) { octray::read_pfm(p); }, path).find("malformed PFM header") != std::string::npos);
    write("PF\n2 2\n-1.0\n" + std::string(20, '\0'));
    CHECK(error_of([](const std::string& p) { octray::read_pfm(p); }, path).find("truncated") != std::string::npos);
    std::filesystem::remove(path);
}
