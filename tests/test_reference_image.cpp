// tests/test_reference_image.cpp — the oracle's display side checked against
// values worked out by hand (the arithmetic is in the comments) from the
// tone-map rules of docs/shading-model.md: the tone-map modes, gamma,
// non-finite radiance, 8-bit quantization, and whole small images.
#include "reference_fixtures.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace octray;
using namespace octray::reference;
using namespace reference_fixtures;

// ----------------------------------------------------------- tone mapping ----

TEST_CASE("tonemap: max_to_one, clamp_to_color, saturate") {
    RenderSettings rs;  // max_to_one, gamma 1
    CHECK_VEC(tonemap({2, 1, 0.5}, rs), Vec3d(1, 0.5, 0.25));       // divide by 2
    CHECK_VEC(tonemap({0.5, 0.2, 1}, rs), Vec3d(0.5, 0.2, 1));      // max == 1: unchanged
    CHECK_VEC(tonemap({0.5, 4, 1}, rs), Vec3d(0.125, 1, 0.25));     // divide by 4

    rs.tonemap = ToneMap::clamp_to_color;  // default clamp colour red
    CHECK_VEC(tonemap({1.5, 0.2, 0.2}, rs), Vec3d(1, 0, 0));
    CHECK_VEC(tonemap({1, 1, 1}, rs), Vec3d(1, 1, 1));             // not > 1
    CHECK_VEC(tonemap({0.3, 0.2, 0.1}, rs), Vec3d(0.3, 0.2, 0.1));
    rs.clamp_color = {0, 0.5, 1};
    CHECK_VEC(tonemap({0.2, 0.2, up(1.0)}, rs), Vec3d(0, 0.5, 1));

    rs.tonemap = ToneMap::saturate;
    CHECK_VEC(tonemap({1.5, 0.5, -0.25}, rs), Vec3d(1, 0.5, 0));
}

TEST_CASE("tonemap: gamma after the tone map") {
    RenderSettings rs;
    rs.gamma = 2;  // c^(1/2)
    CHECK_VEC(tonemap({0.25, 0.0625, 1}, rs), Vec3d(0.5, 0.25, 1));
    // (4,1,0.25) -> max_to_one (1,0.25,0.0625) -> sqrt (1,0.5,0.25).
    CHECK_VEC(tonemap({4, 1, 0.25}, rs), Vec3d(1, 0.5, 0.25));
    rs.gamma = 2.2;
    CHECK(tonemap({0.5, 0, 0}, rs).x == near(std::pow(0.5, 1 / 2.2)));
}

TEST_CASE("tonemap: non-finite radiance maps into gamut") {
    RenderSettings rs;
    // inf components -> 1, finite ones -> 0 (the limit of c/max c); NaN -> 0.
    CHECK_VEC(tonemap({kInf, 2, kNaN}, rs), Vec3d(1, 0, 0));
    CHECK_VEC(tonemap({kInf, kInf, 1}, rs), Vec3d(1, 1, 0));
    CHECK_VEC(tonemap({kNaN, kNaN, kNaN}, rs), Vec3d(0, 0, 0));
    CHECK_VEC(tonemap({-kInf, 0.5, 0}, rs), Vec3d(0, 0.5, 0));
    rs.tonemap = ToneMap::clamp_to_color;
    CHECK_VEC(tonemap({0, kInf, 0}, rs), Vec3d(1, 0, 0));
    CHECK_VEC(tonemap({kNaN, 0.5, 0.5}, rs), Vec3d(0, 0.5, 0.5));
    rs.tonemap = ToneMap::saturate;
    CHECK_VEC(tonemap({kInf, kNaN, -kInf}, rs), Vec3d(1, 0, 0));
}

TEST_CASE("to_8bit: floor(255 c + 0.5) at the half-step boundaries") {
    CHECK(to_8bit(0.0) == 0);
    CHECK(to_8bit(1.0) == 255);
    CHECK(to_8bit(0.5) == 128);  // 127.5 + 0.5 = 128: halves round up
    // The 0/1 boundary is c = 0.5/255; the 254/255 boundary is 254.5/255.
    CHECK(to_8bit(0.5 / 255 + 1e-12) == 1);
    CHECK(to_8bit(0.5 / 255 - 1e-12) == 0);
    CHECK(to_8bit(254.5 / 255 + 1e-12) == 255);
    CHECK(to_8bit(254.5 / 255 - 1e-12) == 254);
    CHECK(to_8bit(100.0 / 255) == 100);
    CHECK(to_8bit(-0.1) == 0);
    CHECK(to_8bit(2.0) == 255);
    CHECK(to_8bit(kNaN) == 0);
    CHECK(to_8bit(kInf) == 255);
}

// ---------------------------------------------------------- whole image ----

TEST_CASE("render and to_display: a 5x3 image by hand") {
    Scene s = pole_scene();
    s.camera = camera_5x3(CameraType::pinhole, {0, 0, 5});
    s.background = {0.2, 0.4, 0.6};
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};
    s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 1.0, false});
    const Image<double> hdr = render(s);
    REQUIRE(hdr.width == 5);
    REQUIRE(hdr.height == 3);
    // Centre pixel (2,1): the pole; L = (0.25 + 0.65/pi) cd = 0.456901... * (1,0.5,0.25).
    const double k = 0.25 + 0.65 / kPi;
    CHECK(hdr.pixel(2, 1)[0] == near(k));
    CHECK(hdr.pixel(2, 1)[1] == near(k * 0.5));
    CHECK(hdr.pixel(2, 1)[2] == near(k * 0.25));
    // Corner (0,0): ray (-4,2,-3)/sqrt29 from (0,0,5); its distance from the centre is
    // |f x d| = |(-10,-20,0)|/sqrt29 = sqrt(500/29) > 1 -> background.
    CHECK(hdr.pixel(0, 0)[0] == 0.2);
    CHECK(hdr.pixel(0, 0)[2] == 0.6);

    const ImageRGB8 img = to_display(hdr, s.render);
    // 255*0.456901 = 116.51 -> 117; 255*0.228451 = 58.25 -> 58; 255*0.114225 = 29.13 -> 29.
    CHECK(int(img.pixel(2, 1)[0]) == 117);
    CHECK(int(img.pixel(2, 1)[1]) == 58);
    CHECK(int(img.pixel(2, 1)[2]) == 29);
    // Background 255*(0.2,0.4,0.6) = (51,102,153).
    CHECK(int(img.pixel(0, 0)[0]) == 51);
    CHECK(int(img.pixel(0, 0)[1]) == 102);
    CHECK(int(img.pixel(0, 0)[2]) == 153);
}

TEST_CASE("render: orthographic rays are parallel") {
    // Orthographic 5x3, height_world 2, facing a disk of radius 0.5 at the origin: only
    // the centre pixel (origin (0,0,5)) hits; pixel (1,1) starts at x = sx =
    // (2*1.5/5 - 1)*1*5/3 = -2/3, outside the disk -> background.
    Scene s;
    s.materials.push_back({"m", 1.0, 0.0, {1, 1, 1}});
    s.objects.push_back({Disk{{0, 0, 0}, {0, 0, 1}, 0.5}, 0});
    s.ambient = AmbientLight{{1, 1, 1}, 0.5};
    s.camera = camera_5x3(CameraType::orthographic, {0, 0, 5});
    const Image<double> hdr = render(s);
    CHECK(hdr.pixel(2, 1)[0] == near(0.5));  // ka cd * ls cl = 1*1*0.5
    CHECK(hdr.pixel(1, 1)[0] == 0.0);
    CHECK(hdr.pixel(2, 0)[0] == 0.0);        // sy = 2/3 > 0.5
}
