// PNG (8-bit) and EXR (float) round trips through OpenImageIO.
#include <gtest/gtest.h>

#include <filesystem>

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

TEST(ImageIo, MissingFileThrows) {
  EXPECT_THROW(read_png("/nonexistent/dir/x.png"), ImageIoError);
  EXPECT_THROW(write_png("/nonexistent/dir/x.png", Image8(1, 1)), ImageIoError);
}
