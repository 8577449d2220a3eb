// tests/support/model_fixtures.hpp — what the model-file tests (test_model_loader.cpp,
// test_model_files.cpp, test_model_ply*.cpp, test_model_obj.cpp,
// test_mesh_transform.cpp, test_mesh_generators.cpp) share: where assimp-testmodels
// is, a temporary folder for files the tests write, the ModelError of a read or a
// load, and bounding boxes.
//
// Real models come from Debian's assimp-testmodels (OCTRAY_ASSIMP_MODELS, found at
// configure time; tools/install-deps installs it). Broken files are written by the
// tests into a temporary folder.
#pragma once

#include "model_loader.hpp"

#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace model_fixtures {

namespace fs = std::filesystem;
using namespace octray;

#ifdef OCTRAY_ASSIMP_MODELS
inline const std::string kModels = OCTRAY_ASSIMP_MODELS;
#else
inline const std::string kModels;
#endif

// The folder of assimp-testmodels, or "" (with a message and a warning) when absent.
inline bool have_models() {
    if (!kModels.empty() && fs::exists(kModels)) return true;
    MESSAGE("assimp-testmodels is not installed (tools/install-deps installs it): test skipped");
    WARN_MESSAGE(false, "real-model test skipped");
    return false;
}

inline std::string model(const std::string& rel) { return kModels + "/" + rel; }

// A fresh folder under the system's temporary folder, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() /
               ("octray-model-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        const fs::path p = path / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }
};

inline std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The same positions, exactly, in the same order.
inline void check_positions(const std::vector<Vec3d>& got, const std::vector<Vec3d>& want) {
    REQUIRE(got.size() == want.size());
    for (std::size_t v = 0; v < want.size(); ++v) {
        CAPTURE(v);
        CHECK(got[v].x == want[v].x);
        CHECK(got[v].y == want[v].y);
        CHECK(got[v].z == want[v].z);
    }
}

// The ModelError message of read(bytes), one of model_formats' readers, or "" when it
// reads; any other exception fails the test where it is thrown.
template <class Reader>
std::string read_error(Reader read, const std::string& bytes) {
    try {
        read(bytes);
    } catch (const ModelError& e) {
        return e.what();
    }
    return "";
}

// The ModelError message of load_model(path, t), or "" when it loads.
inline std::string load_error(const std::string& path, const MeshTransform& t = {}) {
    try {
        load_model(path, t);
    } catch (const ModelError& e) {
        return e.what();
    }
    return "";
}

struct Bounds {
    Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
    Vec3d hi = -lo;
    void add(const Vec3d& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
};

inline Bounds bounds_of(const MeshData& m) {
    Bounds b;
    for (std::uint32_t i : m.indices) b.add(m.vertices[i]);
    return b;
}

// Every coordinate of both corners within tol.
inline void check_bounds(const Bounds& got, const Bounds& want, double tol) {
    const double g[6] = {got.lo.x, got.lo.y, got.lo.z, got.hi.x, got.hi.y, got.hi.z};
    const double w[6] = {want.lo.x, want.lo.y, want.lo.z, want.hi.x, want.hi.y, want.hi.z};
    for (int i = 0; i < 6; ++i) {
        CAPTURE(i);
        CHECK(std::fabs(g[i] - w[i]) <= tol);
    }
}

}  // namespace model_fixtures
