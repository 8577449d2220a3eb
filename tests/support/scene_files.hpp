// tests/support/scene_files.hpp — the JSON scenes of scenes/, and those the build
// generates (OCTRAY_GENERATED_SCENES: the orthographic sphere fields, the
// models under shadow-casting lights; tests/CMakeLists.txt), sorted, for the
// suites that run every one.
#pragma once

#include <doctest/doctest.h>

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/packet_scene.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

// Never empty: a test case that asks for the scenes stops here when there are
// none (a moved folder must not turn "every scene passes" into "no scene ran"),
// so callers may loop, or take front(), without checking.
inline std::vector<std::string> scene_files() {
    std::vector<std::string> files;
    const std::string dir = std::string(OCTRAY_SOURCE_DIR) + "/scenes";
    std::vector<std::string> dirs = {dir};
#ifdef OCTRAY_GENERATED_SCENES
    dirs.push_back(OCTRAY_GENERATED_SCENES);
#endif
    for (const std::string& d : dirs)
        if (std::filesystem::is_directory(d))
            for (const auto& e : std::filesystem::directory_iterator(d))
                if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    REQUIRE_MESSAGE(!files.empty(), "no *.json scenes in " << dir);
    return files;
}

// Calls fn(scene, packet, reference) for every scene of scenes/, loaded,
// compiled and rendered by the reference, with the file name captured.
template <class Fn>
void for_each_scene_file(Fn&& fn) {
    for (const std::string& file : scene_files()) {
        CAPTURE(file);
        const octray::Scene scene = octray::load_scene(file);
        const octray::PacketScene packet = octray::compile(scene);
        const octray::ReferenceRender reference = octray::render_reference(scene);
        fn(scene, packet, reference);
    }
}
