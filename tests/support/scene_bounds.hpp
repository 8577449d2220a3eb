// tests/support/scene_bounds.hpp — every scene of scenes/ at a small width against the
// double reference, a kernel held to its mode's `octray errtime` bound
// (harness/verify.hpp, mode_tolerance) on every lane where both hit the same
// primitive: no band around box edges, outlines or creases is left out, only
// silhouettes and shadow boundaries, as errtime and verify leave them.
// test_scene_bounds.cpp runs every unit; test_perturbed_estimates.cpp the
// units whose estimates sit at their specification's limits.
#pragma once

#include <doctest/doctest.h>

#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/render.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace octray::scene_bounds {

// Small enough for every scene x unit x mode in CI (aobench's reference, 64
// occlusion samples a pixel, is the slow part), large enough that a box's
// faces, a crease and the outlines span many lanes.
inline constexpr int kWidth = 96;

struct SmallScene {
    std::string name;  // file name in scenes/
    Scene scene;
    PacketScene packet;
    ReferenceRender ref;
};

// scenes/*.json at kWidth (aspect kept, as `octray render --width`), compiled
// and rendered by the reference once for the whole run.
inline const std::vector<std::unique_ptr<SmallScene>>& small_scenes() {
    static const std::vector<std::unique_ptr<SmallScene>> all = [] {
        std::vector<std::string> files;
        for (const auto& e : std::filesystem::directory_iterator(std::string(OCTRAY_SOURCE_DIR) + "/scenes"))
            if (e.path().extension() == ".json") files.push_back(e.path().string());
        std::sort(files.begin(), files.end());
        std::vector<std::unique_ptr<SmallScene>> out;
        for (const std::string& file : files) {
            Scene scene = load_scene(file);
            const double aspect = double(scene.camera.height) / scene.camera.width;
            scene.camera.height = std::max(1, int(std::lround(kWidth * aspect)));
            scene.camera.width = kWidth;
            PacketScene packet = compile(scene);
            ReferenceRender ref = render_reference(scene);
            out.push_back(std::make_unique<SmallScene>(
                SmallScene{std::filesystem::path(file).filename().string(), std::move(scene), std::move(packet), std::move(ref)}));
        }
        return out;
    }();
    REQUIRE_MESSAGE(all.size() >= 20, "scenes/ holds " << all.size() << " scenes");
    return all;
}

// Renders s with k (precision p, named `label`) and checks errtime's verdict:
// max L/S within mode_tolerance(p), mismatched hits only on silhouettes (at
// most 0.5% of lanes), no NaN or inf. Returns the agreement.
inline Agreement check_within(const SmallScene& s, const Kernel& k, Precision p, const std::string& label) {
    REQUIRE(bool(k.intersect));
    const PacketRender out = render_packet(k, s.packet);
    const Agreement a = compare(s.ref, out.radiance, out.primitive);
    const Tolerance tol = mode_tolerance(p);
    INFO(s.name << " " << label << ": max L/S " << a.max_scaled << " (bound " << tol.scaled_error << "), mismatched "
                << a.mismatched << " (on silhouettes " << a.mismatched_silhouette << ") of " << a.lanes
                << ", non-finite " << a.nonfinite);
    CHECK(a.max_scaled <= tol.scaled_error);
    CHECK(a.mismatched == a.mismatched_silhouette);
    CHECK(a.within(tol));
    CHECK(a.compared > a.lanes / 2);
    return a;
}

}  // namespace octray::scene_bounds
