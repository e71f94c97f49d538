#include "marionette_ar/render/image.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include "marionette/core/limits.hpp"

namespace marionette::ar {
namespace {

// Reads the header only and checks its size against the library's limits before any
// pixel is decoded (a 50-byte header can declare 80000 x 40000 pixels).
bool sizeWithinLimits(OIIO::ImageBuf& buf, const std::string& name, Diagnostics& diagnostics) {
  if (!buf.init_spec(buf.name(), 0, 0)) {
    diagnostics.error(name, "cannot read the image: " + buf.geterror());
    return false;
  }
  const OIIO::ImageSpec& spec = buf.spec();
  if (const std::string problem = limits::imageSizeProblem(spec.width, spec.height, spec.nchannels); !problem.empty()) {
    diagnostics.error(name, "the image " + problem);
    return false;
  }
  return true;
}

bool toRgba8(OIIO::ImageBuf& buf, const std::string& name, Image8& out, Diagnostics& diagnostics) {
  if (!buf.init_spec(buf.name(), 0, 0) && buf.has_error()) {
    diagnostics.error(name, "cannot read the image: " + buf.geterror());
    return false;
  }
  const OIIO::ImageSpec& spec = buf.spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    diagnostics.error(name, "the image is empty");
    return false;
  }
  out.width = spec.width;
  out.height = spec.height;
  out.channels = 4;
  out.pixels.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height) * 4, 255);
  // Grey, grey+alpha, RGB and RGBA all become RGBA.
  const int n = spec.nchannels;
  const int channelOrder[4] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0, n == 2 ? 1 : (n >= 4 ? 3 : -1)};
  const float fill[4] = {0, 0, 0, 1};
  OIIO::ImageBuf rgba = OIIO::ImageBufAlgo::channels(buf, 4, channelOrder, fill);
  if (rgba.has_error() || !rgba.get_pixels(OIIO::ROI(0, out.width, 0, out.height, 0, 1, 0, 4), OIIO::TypeDesc::UINT8,
                                           out.pixels.data())) {
    diagnostics.error(name, "cannot decode the image: " +
                                (rgba.has_error() ? rgba.geterror() : std::string("unknown")));
    return false;
  }
  return true;
}

}  // namespace

bool readImage(const std::string& path, Image8& out, Diagnostics& diagnostics) {
  if (!OIIO::Filesystem::is_regular(path)) {
    diagnostics.error(path, "no such file");
    return false;
  }
  OIIO::ImageBuf buf(path);
  if (!sizeWithinLimits(buf, path, diagnostics)) return false;
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    diagnostics.error(path, "cannot read the image: " + buf.geterror());
    return false;
  }
  return toRgba8(buf, path, out, diagnostics);
}

bool readImage(std::span<const unsigned char> bytes, const std::string& name, Image8& out, Diagnostics& diagnostics) {
  // OpenImageIO reads from memory through an IOProxy; the format is found from the bytes.
  OIIO::Filesystem::IOMemReader reader(const_cast<unsigned char*>(bytes.data()), bytes.size());
  OIIO::ImageSpec config;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &reader);
  std::string format;
  if (bytes.size() >= 8 && bytes[0] == 0x89 && bytes[1] == 'P') format = "png";
  else if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8) format = "jpeg";
  else {
    diagnostics.error(name, "the embedded image is neither PNG nor JPEG");
    return false;
  }
  OIIO::ImageBuf buf("in_memory." + format, 0, 0, nullptr, &config, &reader);
  if (!sizeWithinLimits(buf, name, diagnostics)) return false;
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    diagnostics.error(name, "cannot decode the embedded image: " + buf.geterror());
    return false;
  }
  return toRgba8(buf, name, out, diagnostics);
}

bool writeImage(const std::string& path, const Image8& image, Diagnostics& diagnostics) {
  if (image.empty() || image.width <= 0 || image.height <= 0) {
    diagnostics.error(path, "nothing to write (empty image)");
    return false;
  }
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, image.pixels.data()) ||
      !out->close()) {
    diagnostics.error(path, "cannot write the image: " + (out ? out->geterror() : OIIO::geterror()));
    return false;
  }
  return true;
}

}  // namespace marionette::ar
