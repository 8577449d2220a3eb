// io/ply_reader.cpp — read_ply (model_formats.hpp). Placeholder: being written.
#include "model_formats.hpp"

namespace octray::model_formats {

RawModel read_ply(std::string_view) { throw ModelError("ply reader not written yet"); }

}  // namespace octray::model_formats
