// Mirror-ball light probes: photos of a perfectly reflective sphere, converted to the
// lat-long EnvironmentMap (environment_map.hpp) so that everything downstream (SH projection,
// transfer) sees one format.
//
// Convention. An orthographic view of the ball, the camera looking along world -Z; image +x
// (columns, left to right) is world +X, image up (rows, bottom to top) is world +Y:
//
//        .-""""""-.          ball point (a, b) in the unit disc, a right, b up:
//      /     +Y     \          normal     n = (a, b, sqrt(1 - a^2 - b^2))
//     |  -X  +Z  +X  |         view       d = (0, 0, -1)
//      \     -Y     /          reflected  r = d - 2 (d.n) n
//        `-......-'                         = (2 c a, 2 c b, 2 c^2 - 1),  c = n.z
//     (+-X, +-Y at radius      Inverse for a direction w: n = normalize(w + (0, 0, 1)),
//      1/sqrt(2); rim: -Z)      (a, b) = (n.x, n.y).
//
//   - The centre of the ball reflects +Z, straight back toward the camera; the rim reflects
//     -Z, straight behind the ball. The point at radius 1/sqrt(2) to the right reflects +X,
//     the one above the centre at that radius +Y (the angle from +Z is 2 asin(radius)).
//   - Orthographic projection gives the mirror ball a uniform density: every unit of ball
//     area (in the unit disc) covers 4 steradians, so a ball of radius R pixels spends
//     4 / R^2 sr per pixel everywhere. The shape is not kept, though: toward the rim the
//     radial direction is squeezed (all of the rim is the one direction -Z), so a cap around
//     -Z is poorly sampled in any real or rendered ball. Treat the directions within ~20
//     degrees of -Z as unreliable.
//
// Image coordinates: pixel (column i, row j), rows top to bottom, covers [i, i+1] x [j, j+1]
// with its centre at (i + 0.5, j + 0.5); y grows downward. A pixel belongs to the ball when
// its centre lies within the circle (distance <= radius); no other pixel is ever read.
#pragma once
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <optional>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/environment_map.hpp"

namespace marionette::prt {

// The ball's outline in image pixels (see the image coordinates above).
struct MirrorBallCircle {
  double centerX = 0.0;
  double centerY = 0.0;
  double radius = 0.0;
};

struct MirrorBallOptions {
  // Empty: the largest centred circle, centre (width/2, height/2), radius min(width, height)/2.
  // Set it for a cropped photo. It must lie within the image (up to half a pixel) and have a
  // radius of at least 1 pixel.
  std::optional<MirrorBallCircle> circle;
  // Width of the lat-long map (height = width / 2); must be even and >= 4. 0: twice the
  // ball's diameter rounded to an even number (at least 8). The ball holds pi R^2 pixels of
  // 4 / R^2 sr each; a lat-long map of width W has (2 pi / W)^2 sr pixels at the equator, so
  // W = pi R would match it; 2 D = 4 R oversamples the equator 1.27x in each direction, which
  // keeps most of the ball's tangential detail near the rim, at 1.6x the pixels.
  int outputWidth = 0;
};

// World direction (unit) reflected by the ball point (a, b); a point outside the unit disc is
// taken at the rim in its direction (the rim reflects -Z).
[[nodiscard]] glm::dvec3 mirrorBallDirection(const glm::dvec2& ballPoint) noexcept;

// Ball point (a, b) in the unit disc reflecting `direction` (need not be normalized):
// radius sin(angle from +Z / 2), polar angle atan2(y, x). Numerically stable up to the rim;
// -Z itself (any rim point reflects it) gives (1, 0), the zero vector gives (0, 0).
[[nodiscard]] glm::dvec2 mirrorBallPoint(const glm::dvec3& direction) noexcept;

// Converts a mirror-ball image (`rgb`: width*height*3 linear floats, rows top to bottom) to a
// lat-long map. Each lat-long pixel is integrated with k x k sub-samples (k from 2 to 8,
// chosen from the size of the pixel's footprint on the ball, weighted by solid angle), each a
// bilinear sample of the ball image using only ball pixels (weights renormalized at the rim).
// Errors go to `diagnostics` under the name `source` (the file, when there is one) and leave
// the result empty: no pixels or no data, a circle that is not finite, smaller than 1 pixel or
// beyond the image, a bad output width.
[[nodiscard]] std::optional<EnvironmentMap> mirrorBallToLatLong(const float* rgb, int width, int height,
                                                                const MirrorBallOptions& options,
                                                                Diagnostics& diagnostics,
                                                                const std::string& source = "mirror ball");

// The forward helper (tests, docs, previews): the size x size image an orthographic camera
// sees of a mirror ball of diameter `size` reflecting `map`, rows top to bottom, RGB
// interleaved; black outside the ball. Each ball pixel averages subsamples x subsamples
// bilinear samples of the map (those inside the circle). Empty for size < 1.
[[nodiscard]] std::vector<float> renderMirrorBall(const EnvironmentMap& map, int size, int subsamples = 4);

enum class LightProbeKind {
  LatLong,     // exactly loadEnvironmentMap
  MirrorBall,  // converted with mirrorBallToLatLong
  Auto,        // square (1:1): mirror ball; otherwise lat-long (not 2:1: with the aspect warning)
};

// Loads a light probe file (.hdr, .exr, anything OpenImageIO reads) as a lat-long map, with
// loadEnvironmentMap's reading, channel rules, clamping (one warning naming the file) and
// errors (each naming the file). `options` applies to mirror balls only.
[[nodiscard]] EnvironmentMapLoad loadLightProbe(const std::string& path, LightProbeKind kind = LightProbeKind::Auto,
                                                const MirrorBallOptions& options = {});

}  // namespace marionette::prt
