// fuzz/scene_loader_fuzz.cpp — the scene JSON loader on any bytes (docs/reliability.md).
//
// The loader's promise (io/scene_loader.hpp): any text gets a Scene or a
// SceneError whose what() is one line starting with the file name. Anything
// else is a bug: another exception type, a crash, a sanitizer report, a
// multi-line message. A Scene it accepts must also pass validate() and
// compile(), and the kernels must trace it within the numerical policy: a few
// camera tiles (first, middle and last row) go through intersect, occluded,
// shade and tonemap of the SIMD and scalar paths, checked by
// tests/support/kernel_checks.hpp.
#include "kernel_checks.hpp"
#include "scene_loader.hpp"

#include <octray/kernels.hpp>
#include <octray/packet_scene.hpp>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "scene_loader_fuzz: %s\n", what.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string file = "fuzz.json";
    octray::Scene scene;
    try {
        scene = octray::parse_scene(std::string(reinterpret_cast<const char*>(data), size), file);
    } catch (const octray::SceneError& e) {
        // The normal answer to a bad file: one line, naming the file.
        const std::string what = e.what();
        if (what.rfind(file + ": ", 0) != 0) bug("error message does not start with the file name: " + what);
        if (what.find('\n') != std::string::npos) bug("error message is not one line: " + what);
        return 0;
    } catch (const std::exception& e) {
        bug(std::string("parse_scene threw something other than SceneError: ") + e.what());
    }
    try {
        octray::validate(scene);
        if (const std::string e = octray::test::trace_camera_tiles(scene); !e.empty()) bug(e);
    } catch (const std::exception& e) {
        bug(std::string("the loader accepted a scene that validate() or compile() rejects: ") + e.what());
    }
    return 0;
}
