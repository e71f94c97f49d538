// HDR lat-long (equirectangular) environment maps in linear float RGB.
//
// Convention (the renderer: +Y up, right-handed, the character faces +Z, so a camera in
// front of it looks along -Z):
//   - u in [0, 1] runs along the azimuth, left to right over the image columns;
//     v in [0, 1] runs from the top row (+Y, the zenith) to the bottom row (-Y, the nadir).
//   - The image centre (u = 0.5, v = 0.5) is the direction -Z: a camera in front of the
//     character, looking at it, sees the middle of the panorama behind it. u = 0.75 is +X
//     (to the right of that view), u = 0.25 is -X, u = 0 and u = 1 are +Z (behind the camera).
//   - direction(u, v) = (sin(theta) sin(phi), cos(theta), -sin(theta) cos(phi)) with
//     theta = pi v (polar angle from +Y) and phi = 2 pi (u - 0.5).
//     Inverse, e.g. in a shader: u = 0.5 + atan(d.x, -d.z) / (2 pi), v = acos(d.y) / pi.
//   - Pixel (column c, row r) covers u in [c/W, (c+1)/W] and v in [r/H, (r+1)/H]; its
//     centre is at ((c + 0.5)/W, (r + 0.5)/H).
//
// Data layout: `pixels` is width*height*3 floats, RGB interleaved, rows top (+Y) to bottom,
// no padding: it uploads as-is as a GL_RGB32F (or GL_RGB16F) texture, with the first row
// at t = 0 (sample with t = v; do not flip).
#pragma once
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::prt {

class EnvironmentMap {
 public:
  EnvironmentMap() = default;
  // `rgb` must hold width*height*3 linear values (rows top to bottom). Values are taken as
  // given (loadEnvironmentMap does the clamping of negative, NaN and Inf values).
  EnvironmentMap(int width, int height, std::vector<float> rgb);

  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }
  [[nodiscard]] const std::vector<float>& pixels() const noexcept { return pixels_; }
  [[nodiscard]] std::vector<float>& pixels() noexcept { return pixels_; }
  [[nodiscard]] glm::vec3 texel(int column, int row) const noexcept {
    const float* p = &pixels_[(static_cast<std::size_t>(row) * width_ + column) * 3];
    return {p[0], p[1], p[2]};
  }

  // Unit direction of the point (u, v) of the map (see the convention above).
  [[nodiscard]] static glm::dvec3 direction(double u, double v) noexcept;
  // (u, v) of a direction (need not be normalized; the zero vector gives (0.5, 0.5)).
  [[nodiscard]] static glm::dvec2 uv(const glm::dvec3& direction) noexcept;
  // Direction of the centre of a pixel.
  [[nodiscard]] glm::dvec3 texelDirection(int column, int row) const noexcept;
  // Exact solid angle (steradians) of one pixel of a row: dphi * (cos theta0 - cos theta1),
  // dphi = 2 pi / width, theta0 = pi row / height, theta1 = pi (row + 1) / height.
  // The pixels of the whole map sum to 4 pi.
  [[nodiscard]] double texelSolidAngle(int row) const noexcept;

  // Bilinear sample of the radiance toward `direction` (wraps around in azimuth, clamps at
  // the poles), between pixel centres as a GL_LINEAR texture with GL_REPEAT in s and
  // GL_CLAMP_TO_EDGE in t would.
  [[nodiscard]] glm::vec3 sample(const glm::dvec3& direction) const noexcept;

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<float> pixels_;
};

struct EnvironmentMapLoad {
  std::optional<EnvironmentMap> map;  // empty when loading failed
  Diagnostics diagnostics;            // errors and warnings, each naming the file
};

// Loads a lat-long HDR image (.hdr Radiance RGBE, .exr OpenEXR with any compression
// OpenEXR decodes, DWAB included; anything else OpenImageIO reads) as linear float RGB.
//   - Channels: 1 channel is grey (copied to R, G and B); 2 channels are grey + alpha;
//     3 or more: the first three are R, G, B (alpha and extra channels dropped). EXR channels
//     are taken in R, G, B order whatever their order in the file.
//   - Negative and NaN values become 0; +Inf becomes 0 as well (an infinite radiance has no
//     meaningful finite stand-in and would dominate any integral), -Inf too. One warning names
//     the file and how many values were changed.
//   - Aspect ratio: a lat-long map is 2:1. Any other ratio is still read as lat-long (the
//     mapping above only needs u and v) with a warning, since the file is most likely a
//     different projection (cube cross, mirror ball) or a cropped panorama.
//   - Errors (map empty): missing file, unreadable or undecodable file, 0 pixels. Each error
//     names the file.
[[nodiscard]] EnvironmentMapLoad loadEnvironmentMap(const std::string& path);

}  // namespace marionette::prt
