// tests/scene_files.hpp — the JSON scenes of scenes/, sorted, for the suites that run every one.
#pragma once

#include <doctest/doctest.h>

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
    if (std::filesystem::is_directory(dir))
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    REQUIRE_MESSAGE(!files.empty(), "no *.json scenes in " << dir);
    return files;
}
