// fuzz/ply_fuzz.cpp — read_ply (io/ply_reader.cpp) on any bytes, then everything a
// loaded model goes through (model_fuzz_checks.hpp).
#include "model_fuzz_checks.hpp"

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    return model_fuzz::run([&] { return octray::model_formats::read_ply(bytes); }, "PLY");
}
