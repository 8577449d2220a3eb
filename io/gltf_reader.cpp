// io/gltf_reader.cpp — read_gltf (model_formats.hpp). Placeholder: being written.
#include "model_formats.hpp"

namespace octray::model_formats {

RawModel read_gltf(std::string_view, bool, const std::filesystem::path&) {
    throw ModelError("glTF reader not written yet");
}

}  // namespace octray::model_formats
