// Image files through OpenImageIO: 8-bit PNG for device/reference frames, EXR (float) for the
// linear reference. Errors throw ImageIoError naming the file.
#pragma once

#include <filesystem>
#include <stdexcept>

#include "host/image.hpp"

namespace tp::host {

class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void write_png(const std::filesystem::path& file, const Image8& image);
Image8 read_png(const std::filesystem::path& file);  // any 8-bit image OIIO reads; RGB kept
void write_exr(const std::filesystem::path& file, const FloatImage& image);
FloatImage read_exr(const std::filesystem::path& file);

}  // namespace tp::host
