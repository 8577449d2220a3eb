// io/obj_reader.cpp — read_obj (model_formats.hpp). Placeholder: being written.
#include "model_formats.hpp"

namespace octray::model_formats {

RawModel read_obj(std::string_view) { throw ModelError("obj reader not written yet"); }

}  // namespace octray::model_formats
