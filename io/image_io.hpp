// io/image_io.hpp — PNG (8-bit display images) and PFM (HDR radiance) files.
//
// PFM is the standard little-endian colour variant: header "PF\n<w> <h>\n-1.0\n",
// then float32 RGB rows from the BOTTOM of the image to the top (the PFM convention).
// Every failure throws std::runtime_error naming the file and the OS reason.
#pragma once

#include <octray/image.hpp>

#include <string>

namespace octray {

void write_png(const std::string& path, const ImageRGB8& image);
ImageRGB8 read_png(const std::string& path);  // any PNG, converted to RGB

void write_pfm(const std::string& path, const Image<float>& image);
void write_pfm(const std::string& path, const Image<double>& image);  // stored as float32
Image<float> read_pfm(const std::string& path);  // rows returned top to bottom

}  // namespace octray
