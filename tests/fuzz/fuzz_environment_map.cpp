// libFuzzer target: light-probe images (Radiance .hdr, OpenEXR, anything OpenImageIO
// decodes), read by prt::loadEnvironmentMap from a temporary file (.exr when the input
// starts with the EXR magic, else .hdr), and, for small ones, by prt::loadLightProbe as
// a mirror ball. Contract: no crash, no decode past limits::imageSizeProblem's limits; a
// failure has an error and every diagnostic names the file; a map has width*height*3
// finite, non-negative values. With MARIONETTE_FUZZ_WRITE_SEED=folder the program writes
// tiny seeds there (HDR, EXR in several compressions, a square mirror ball) through
// OpenImageIO and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <OpenImageIO/imageio.h>

#include <cstring>

#include "fuzz_support.hpp"
#include "marionette/prt/mirror_ball.hpp"

using namespace marionette;
using fuzz::require;

namespace {

void writeSeed(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type,
               const char* compression) {
  std::vector<float> pixels(static_cast<std::size_t>(width) * height * channels);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = 0.05f * static_cast<float>(i % 97) * (i % 7 == 0 ? 40 : 1);
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(width, height, channels, type);
  if (compression) spec.attribute("compression", compression);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) || !out->close()) {
    std::fprintf(stderr, "cannot write the seed %s: %s\n", path.c_str(), OIIO::geterror().c_str());
    std::exit(1);
  }
}

void checkMap(const prt::EnvironmentMapLoad& r, const std::string& path) {
  if (!r.map) {
    fuzz::requireNamedFailure(r.diagnostics, path);
    return;
  }
  require(fuzz::allName(r.diagnostics, path), "a warning does not name the file");
  const prt::EnvironmentMap& m = *r.map;
  require(m.width() > 0 && m.height() > 0, "a map without pixels");
  require(m.pixels().size() == static_cast<std::size_t>(m.width()) * m.height() * 3, "pixel count is not w*h*3");
  for (float v : m.pixels()) require(std::isfinite(v) && v >= 0.0f, "a pixel is not finite and non-negative");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    const std::string d = std::string(dir) + "/";
    writeSeed(d + "latlong.hdr", 32, 16, 3, OIIO::TypeDesc::FLOAT, nullptr);
    writeSeed(d + "ball.hdr", 16, 16, 3, OIIO::TypeDesc::FLOAT, nullptr);
    writeSeed(d + "grey.exr", 16, 8, 1, OIIO::TypeDesc::HALF, "none");
    writeSeed(d + "rgba-zip.exr", 16, 8, 4, OIIO::TypeDesc::HALF, "zip");
    writeSeed(d + "rgb-piz.exr", 16, 8, 3, OIIO::TypeDesc::FLOAT, "piz");
    writeSeed(d + "rgb-rle.exr", 16, 8, 3, OIIO::TypeDesc::HALF, "rle");
    writeSeed(d + "rgb-dwab.exr", 64, 32, 3, OIIO::TypeDesc::HALF, "dwab");
    writeSeed(d + "ball.exr", 16, 16, 3, OIIO::TypeDesc::HALF, "zips");
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
  const bool exr = size >= 4 && std::memcmp(data, kExrMagic, 4) == 0;
  const std::string path = fuzz::writeInput(data, size, exr ? "in.exr" : "in.hdr");
  const prt::EnvironmentMapLoad latLong = prt::loadEnvironmentMap(path);
  checkMap(latLong, path);
  // The mirror-ball conversion costs about 16 output pixels per input pixel: small inputs only.
  if (latLong.map && latLong.map->width() <= 64 && latLong.map->height() <= 64)
    checkMap(prt::loadLightProbe(path, prt::LightProbeKind::MirrorBall), path);
  return 0;
}
