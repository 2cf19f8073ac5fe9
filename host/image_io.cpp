#include "host/image_io.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>
#include <span>
#include <vector>

#include "host/replace_file.hpp"

namespace tp::host {

namespace {

// Encodes the image in memory and writes the file whole (replace_file): OpenImageIO's PNG writer
// does not report a write that fails part-way, so a full disk left a cut-off PNG, the old one lost,
// and the command exited 0. The format is the file name's extension's, as OpenImageIO chooses it;
// one whose writer cannot write into memory is refused (PNG, EXR, TIFF, JPEG and most others can).
template <class T>
void write_image(const std::filesystem::path& file, int w, int h, OIIO::TypeDesc type,
                 const T* data) {
  // Declared before the writer, so that they outlive it: an ImageOutput closes itself when it is
  // destroyed, writing through its proxy.
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  auto out = OIIO::ImageOutput::create(file.string());
  if (!out) throw ImageIoError("cannot write " + file.string() + ": " + OIIO::geterror());
  if (!out->supports("ioproxy"))
    throw ImageIoError("cannot write " + file.string() + ": OpenImageIO's " + out->format_name() +
                       " writer cannot write into memory, which writing the file whole needs "
                       "(write .png, .exr or .tif)");
  const OIIO::ImageSpec spec(w, h, 3, type);
  if (!out->set_ioproxy(&memory) || !out->open(file.string(), spec) ||
      !out->write_image(type, data) || !out->close())
    throw ImageIoError("cannot write " + file.string() + ": " + out->geterror());
  try {
    replace_file(file.string(), std::as_bytes(std::span(bytes)));
  } catch (const std::runtime_error& e) {  // "FILE: cannot write: CAUSE", as a stream's
    throw ImageIoError(e.what());
  }
}

// Reads all pixels as `type`, keeping the first three channels (grey, with or without alpha, is
// replicated). The size the file declares is checked before anything is allocated for it: a PNG
// of some sixty bytes can declare 20000 × 20000 pixels. The pixels must be stored as `type`:
// read as 8-bit, a float image's NaN became 0, the background, and its values were rounded
// without a word (found by review, 2026-12-08).
template <class T>
std::vector<T> read_image(const std::filesystem::path& file, OIIO::TypeDesc type, int& w, int& h) {
  auto in = OIIO::ImageInput::open(file.string());
  if (!in) throw ImageIoError("cannot read " + file.string() + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  w = spec.width;
  h = spec.height;
  const int nc = spec.nchannels;
  if (w <= 0 || h <= 0 || spec.depth != 1 || nc <= 0 || nc > kMaxImageChannels ||
      static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > kMaxImagePixels)
    throw ImageIoError("cannot read " + file.string() + ": it declares " + std::to_string(w) +
                       " x " + std::to_string(h) + " pixels of " + std::to_string(nc) +
                       " channels; at most " + std::to_string(kMaxImagePixels) +
                       " pixels of 1 to " + std::to_string(kMaxImageChannels) +
                       " channels are read");
  if (spec.format != type)
    throw ImageIoError("cannot read " + file.string() + ": its pixels are " + spec.format.c_str() +
                       ", not " + type.c_str() +
                       (type == OIIO::TypeDesc::UINT8 ? " (8-bit images, as render writes)" : ""));
  std::vector<T> all(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) *
                     static_cast<std::size_t>(nc));
  if (!in->read_image(0, 0, 0, nc, type, all.data()))
    throw ImageIoError("cannot read " + file.string() + ": " + in->geterror());
  in->close();
  std::vector<T> rgb(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (std::size_t p = 0; p < rgb.size() / 3; ++p)
    for (std::size_t k = 0; k < 3; ++k)
      rgb[3 * p + k] = all[p * static_cast<std::size_t>(nc) + (nc >= 3 ? k : 0)];
  return rgb;
}

}  // namespace

void write_png(const std::filesystem::path& file, const Image8& im) {
  write_image(file, im.width, im.height, OIIO::TypeDesc::UINT8, im.rgb.data());
}

Image8 read_png(const std::filesystem::path& file) {
  Image8 im;
  im.rgb = read_image<std::uint8_t>(file, OIIO::TypeDesc::UINT8, im.width, im.height);
  return im;
}

void write_exr(const std::filesystem::path& file, const FloatImage& im) {
  write_image(file, im.width, im.height, OIIO::TypeDesc::FLOAT, im.rgb.data());
}

FloatImage read_exr(const std::filesystem::path& file) {
  FloatImage im;
  im.rgb = read_image<float>(file, OIIO::TypeDesc::FLOAT, im.width, im.height);
  return im;
}

}  // namespace tp::host
