// bench/bench_model_load.cpp — model files: octray's load_model (io/model_loader.hpp, its
// own readers) against assimp 5.2's Importer::ReadFile, on the same files.
//
//   model_load/<file>/octray   load_model: read, parse, every check, transform, vertices
//                              shared by position, degenerate triangles dropped
//   model_load/<file>/assimp   ReadFile with Triangulate | SortByPType | ValidateDataStructure,
//                              the steps octray's loader asked of assimp before it had its own
//                              readers (its own checks and vertex sharing came on top)
// Files: a 1M-triangle binary PLY (height_field(707) written by save_ply into a scratch
// folder), the largest glTF (2CylinderEngine.glb, 121k triangles) and OBJ (WusonOBJ.obj)
// of assimp-testmodels. Counter triangles: what each read. Wall time, one thread.
#include "mesh_generators.hpp"
#include "model_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

// The generated PLY, written once per process into a scratch folder removed at exit.
struct ScratchPly {
    fs::path dir, file;
    ScratchPly() {
        std::string pattern = (fs::temp_directory_path() / "octray_model_bench.XXXXXX").string();
        if (!mkdtemp(pattern.data())) std::abort();
        dir = pattern;
        file = dir / "height_field_707.ply";
        octray::save_ply(octray::height_field(707), file.string());
    }
    ~ScratchPly() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

std::string path_of(const std::string& name) {
    if (name == "ply_1M") {
        static const ScratchPly ply;
        return ply.file.string();
    }
    const std::string models = OCTRAY_ASSIMP_MODELS;
    if (name == "glb_2CylinderEngine") return models + "/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
    return models + "/OBJ/WusonOBJ.obj";
}

void octray_load(benchmark::State& state, const std::string& name) {
    const std::string path = path_of(name);
    std::size_t triangles = 0;
    for (auto _ : state) {
        const octray::MeshData m = octray::load_model(path);
        triangles = m.triangle_count() + m.dropped_degenerate;
        benchmark::DoNotOptimize(m.vertices.data());
    }
    state.counters["triangles"] = double(triangles);
}

void assimp_load(benchmark::State& state, const std::string& name) {
    const std::string path = path_of(name);
    std::size_t triangles = 0;
    for (auto _ : state) {
        Assimp::Importer imp;
        const aiScene* s =
            imp.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure);
        if (!s) {
            state.SkipWithError(imp.GetErrorString());
            return;
        }
        triangles = 0;
        for (unsigned m = 0; m < s->mNumMeshes; ++m)
            for (unsigned f = 0; f < s->mMeshes[m]->mNumFaces; ++f) triangles += s->mMeshes[m]->mFaces[f].mNumIndices == 3;
        benchmark::DoNotOptimize(s);
    }
    state.counters["triangles"] = double(triangles);
}

const bool registered = [] {
    for (const char* name : {"ply_1M", "glb_2CylinderEngine", "obj_Wuson"}) {
        benchmark::RegisterBenchmark((std::string("model_load/") + name + "/octray").c_str(), octray_load,
                                     std::string(name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
        benchmark::RegisterBenchmark((std::string("model_load/") + name + "/assimp").c_str(), assimp_load,
                                     std::string(name))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    return true;
}();

}  // namespace

BENCHMARK_MAIN();
