// PNG (8-bit) and EXR (float) round trips through OpenImageIO.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>

#include "host/image_io.hpp"

using namespace tp::host;

TEST(ImageIo, PngRoundTripIsExact) {
  Image8 im(5, 3);
  for (std::size_t k = 0; k < im.rgb.size(); ++k)
    im.rgb[k] = static_cast<std::uint8_t>(k * 17 % 256);
  const auto file = std::filesystem::temp_directory_path() / "tp_host_roundtrip.png";
  write_png(file, im);
  const Image8 back = read_png(file);
  EXPECT_EQ(back.width, 5);
  EXPECT_EQ(back.height, 3);
  EXPECT_EQ(back.rgb, im.rgb);
  std::filesystem::remove(file);
}

TEST(ImageIo, ExrRoundTripKeepsFloatsUnclamped) {
  FloatImage im(4, 2);
  for (std::size_t k = 0; k < im.rgb.size(); ++k) im.rgb[k] = 0.1f * static_cast<float>(k) - 0.3f;
  const auto file = std::filesystem::temp_directory_path() / "tp_host_roundtrip.exr";
  write_exr(file, im);
  const FloatImage back = read_exr(file);
  EXPECT_EQ(back.width, 4);
  EXPECT_EQ(back.height, 2);
  EXPECT_EQ(back.rgb, im.rgb);  // 32-bit float EXR: bit exact, values > 1 and < 0 kept
  std::filesystem::remove(file);
}

// Read as 8-bit, a float image's NaN became 0, which compare takes for the background: sixteen
// NaN pixels compared as "0 pixels, colour correctness 1" (found by review, 2026-12-08). An image
// whose pixels are not stored as 8 bits is refused, naming the file and the type.
TEST(ImageIo, AFloatImageIsNotReadAsEightBit) {
  FloatImage im(4, 4);
  std::fill(im.rgb.begin(), im.rgb.end(), std::numeric_limits<float>::quiet_NaN());
  const auto file = std::filesystem::temp_directory_path() / "tp_host_nan.exr";
  write_exr(file, im);
  try {
    (void)read_png(file);
    ADD_FAILURE() << "read";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find("tp_host_nan.exr: its pixels are float, not uint8"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(file);
}

TEST(ImageIo, MissingFileThrows) {
  EXPECT_THROW(read_png("/nonexistent/dir/x.png"), ImageIoError);
  EXPECT_THROW(write_png("/nonexistent/dir/x.png", Image8(1, 1)), ImageIoError);
}
