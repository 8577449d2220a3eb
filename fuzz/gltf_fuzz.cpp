// fuzz/gltf_fuzz.cpp — read_gltf (io/gltf_reader.cpp) on any bytes, then everything a
// loaded model goes through (model_fuzz_checks.hpp). Input starting "glTF" is read as a
// .glb, anything else as .gltf JSON, so real model files are seeds as they are. The
// model's folder is a scratch folder holding one file, buffer.bin (a triangle's three
// float positions), so external buffer URIs are resolved for real.
#include "model_fuzz_checks.hpp"

#include <filesystem>
#include <fstream>
#include <string_view>

#include <unistd.h>

namespace {

struct ScratchDir {
    std::filesystem::path path;
    ScratchDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "octray_gltf_fuzz.XXXXXX").string();
        if (!mkdtemp(pattern.data())) model_fuzz::bug("cannot create a scratch directory");
        path = pattern;
        const float triangle[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        std::ofstream(path / "buffer.bin", std::ios::binary)
            .write(reinterpret_cast<const char*>(triangle), sizeof triangle);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const ScratchDir scratch;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const bool binary = bytes.substr(0, 4) == "glTF";
    return model_fuzz::run([&] { return octray::model_formats::read_gltf(bytes, binary, scratch.path); }, "glTF 2.0");
}
