// compile(): what it rejects in scenes built in code.
#include <doctest/doctest.h>

#include "support.hpp"

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

TEST_CASE("compile() rejects scenes built in code that break the invariants, naming the field") {
    auto message = [](const Scene& s) -> std::string {
        try {
            compile(s);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    Scene ok = one_object_scene(Sphere{{0, 0, 0}, 1});
    CHECK(message(ok).empty());
    Scene bad = ok;
    bad.objects[0].material = 3;
    CHECK(message(bad).find("objects[0].material: index 3, but there are 1 materials") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Sphere{{0, 0, 0}, -1};
    CHECK(message(bad).find("objects[0].radius") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Box{{0, 0, 0}, {1, 0, 1}};
    CHECK(message(bad).find("objects[0]: is degenerate") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    CHECK(message(bad).find("objects[0]: is degenerate") != std::string::npos);
    bad = ok;
    bad.point_lights.push_back(PointLight{{0, NAN, 0}});
    CHECK(message(bad).find("point_lights[0].position[1]: must be finite") != std::string::npos);
    bad = ok;
    bad.camera.up = {0, 0, 1};  // parallel to eye - look_at
    CHECK(message(bad).find("camera.up") != std::string::npos);
}
