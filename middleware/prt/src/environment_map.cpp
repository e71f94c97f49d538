#include "marionette/prt/environment_map.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <utility>

#include "exr_header_check.hpp"

#include "rgb_image_reader.hpp"
#include "marionette/core/limits.hpp"

namespace marionette::prt {

namespace {
constexpr double kPi = std::numbers::pi;

int channelIndex(const OIIO::ImageSpec& spec, const char* name) {
  for (int i = 0; i < spec.nchannels; ++i)
    if (spec.channelnames[i] == name) return i;
  return -1;
}
}  // namespace

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<float> rgb)
    : width_(width), height_(height), pixels_(std::move(rgb)) {
  pixels_.resize(static_cast<std::size_t>(std::max(width_, 0)) * std::max(height_, 0) * 3, 0.0f);
}

glm::dvec3 EnvironmentMap::direction(double u, double v) noexcept {
  const double theta = kPi * v;
  const double phi = 2.0 * kPi * (u - 0.5);
  const double s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

glm::dvec2 EnvironmentMap::uv(const glm::dvec3& d) noexcept {
  const double len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  if (!(len > 0.0)) return {0.5, 0.5};
  double u = 0.5 + std::atan2(d.x, -d.z) / (2.0 * kPi);
  if (u >= 1.0) u -= 1.0;
  const double v = std::acos(std::clamp(d.y / len, -1.0, 1.0)) / kPi;
  return {u, v};
}

glm::dvec3 EnvironmentMap::texelDirection(int column, int row) const noexcept {
  return direction((column + 0.5) / width_, (row + 0.5) / height_);
}

double EnvironmentMap::texelSolidAngle(int row) const noexcept {
  const double dphi = 2.0 * kPi / width_;
  return dphi * (std::cos(kPi * row / height_) - std::cos(kPi * (row + 1) / height_));
}

glm::vec3 EnvironmentMap::sample(const glm::dvec3& dir) const noexcept {
  if (width_ <= 0 || height_ <= 0) return glm::vec3(0.0f);
  const glm::dvec2 t = uv(dir);
  const double x = t.x * width_ - 0.5;
  const double y = std::clamp(t.y * height_ - 0.5, 0.0, static_cast<double>(height_ - 1));
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  auto wrap = [&](long c) { return static_cast<int>(((c % width_) + width_) % width_); };
  const int c0 = wrap(static_cast<long>(fx)), c1 = wrap(static_cast<long>(fx) + 1);
  const int r0 = static_cast<int>(fy), r1 = std::min(r0 + 1, height_ - 1);
  const glm::dvec3 top = glm::dvec3(texel(c0, r0)) * (1.0 - ax) + glm::dvec3(texel(c1, r0)) * ax;
  const glm::dvec3 bottom = glm::dvec3(texel(c0, r1)) * (1.0 - ax) + glm::dvec3(texel(c1, r1)) * ax;
  return glm::vec3(top * (1.0 - ay) + bottom * ay);
}

namespace detail {

std::optional<RgbImage> readRgbImage(const std::string& path, const std::string& noun, Diagnostics& diag) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    diag.error(path, noun + " not found (no such file)");
    return std::nullopt;
  }
  if (std::filesystem::is_directory(path, ec)) {
    diag.error(path, noun + " is a directory, expected an image file (.hdr, .exr)");
    return std::nullopt;
  }
  if (const std::string problem = exrHeaderProblem(path); !problem.empty()) {
    diag.error(path, noun + " " + problem);
    return std::nullopt;
  }
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    diag.error(path, "cannot read the " + noun + " as an image: " + OIIO::geterror());
    return std::nullopt;
  }
  const OIIO::ImageSpec spec = input->spec();
  const int width = spec.width, height = spec.height, nch = spec.nchannels;
  if (width <= 0 || height <= 0 || nch <= 0) {
    diag.error(path, noun + " has no pixels (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
                         std::to_string(nch) + " channels)");
    return std::nullopt;
  }
  if (const std::string problem = limits::imageSizeProblem(width, height, nch); !problem.empty()) {
    diag.error(path, noun + " " + problem);
    return std::nullopt;
  }
  std::vector<float> all(static_cast<std::size_t>(width) * height * nch);
  if (!input->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, all.data())) {
    std::string why = input->geterror();
    diag.error(path, "cannot decode the " + noun + "'s pixels" + (why.empty() ? std::string() : ": " + why));
    return std::nullopt;
  }
  input->close();

  // Which channels are R, G, B.
  int ch[3] = {0, 0, 0};
  if (nch >= 3) {
    const int r = channelIndex(spec, "R"), g = channelIndex(spec, "G"), b = channelIndex(spec, "B");
    if (r >= 0 && g >= 0 && b >= 0) {
      ch[0] = r, ch[1] = g, ch[2] = b;
    } else {
      ch[0] = 0, ch[1] = 1, ch[2] = 2;
    }
  }  // 1 or 2 channels: grey (and alpha): R = G = B = channel 0

  RgbImage image{width, height, std::vector<float>(static_cast<std::size_t>(width) * height * 3)};
  std::vector<float>& rgb = image.rgb;
  std::size_t clamped = 0, nans = 0, infs = 0, negatives = 0;
  const std::size_t count = static_cast<std::size_t>(width) * height;
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      float value = all[i * nch + ch[c]];
      if (std::isnan(value)) {
        ++nans, value = 0.0f;
      } else if (std::isinf(value)) {
        ++infs, value = 0.0f;
      } else if (value < 0.0f) {
        ++negatives, value = 0.0f;
      }
      rgb[i * 3 + c] = value;
    }
  }
  clamped = nans + infs + negatives;
  if (clamped > 0)
    diag.warning(path, std::to_string(clamped) + " pixel values clamped to 0 (" + std::to_string(negatives) +
                           " negative, " + std::to_string(nans) + " NaN, " + std::to_string(infs) + " infinite)");
  return image;
}

void warnIfNotTwoToOne(const std::string& path, int width, int height, Diagnostics& diag) {
  if (width != 2 * height)
    diag.warning(path, "environment map is " + std::to_string(width) + "x" + std::to_string(height) +
                           ", not 2:1; read as lat-long anyway (is it another projection or a cropped panorama?)");
}

}  // namespace detail

EnvironmentMapLoad loadEnvironmentMap(const std::string& path) {
  EnvironmentMapLoad result;
  auto image = detail::readRgbImage(path, "environment map", result.diagnostics);
  if (!image) return result;
  detail::warnIfNotTwoToOne(path, image->width, image->height, result.diagnostics);
  result.map.emplace(image->width, image->height, std::move(image->rgb));
  return result;
}

}  // namespace marionette::prt
