// Image files through OpenImageIO: 8-bit PNG for device/reference frames, EXR (float) for the
// linear reference. Errors throw ImageIoError naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>

#include "host/image.hpp"

namespace tp::host {

class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What the readers accept: twice the device's largest frame (4096 × 4096) in pixels, and grey,
// grey with alpha, RGB or RGBA; a file declaring more is refused before its pixels are read.
inline constexpr std::uint64_t kMaxImagePixels = std::uint64_t{1} << 25;
inline constexpr int kMaxImageChannels = 4;

void write_png(const std::filesystem::path& file, const Image8& image);
// Any image OIIO reads whose pixels are stored as 8 bits (float or 16-bit ones are refused, not
// converted); RGB kept. read_exr likewise takes float pixels only.
Image8 read_png(const std::filesystem::path& file);
void write_exr(const std::filesystem::path& file, const FloatImage& image);
FloatImage read_exr(const std::filesystem::path& file);

}  // namespace tp::host
