// The markerless tracker's map of a planar surface: keyframes that each hold a grey image
// of the surface, the homography from the plane to that image, the corners KLT follows and
// the ORB features relocalization matches. Keyframe 0 is the reference image of the target
// (its plane-to-image map a scale and offset); later keyframes are camera frames taken
// while tracking, so that the map reaches past the target.
//
// Plane coordinates: metres, (X, Z) of the world point (X, 0, Z) (tracker.hpp).
//
// On disk (`--save-map` / `--map`), little-endian:
//   "MNPLANAR" magic, u32 version (1), u32 camera width, u32 camera height,
//   f64 fx fy cx cy k1 k2 p1 p2 k3, f64 target width, f64 target height, u32 keyframes,
//   per keyframe: u32 width, u32 height, f64 planeToImage[9] (row-major), u8 grey[w*h],
//     u32 corners, f32 x y per corner, u32 features,
//     per feature: f32 x y size angle response, i32 octave, u8 descriptor[32],
//   u32 CRC-32 (zlib's polynomial) of every byte before it.
// The reader checks every count against the bytes left and the limits below before it
// allocates, and the checksum before it trusts anything.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"
#include "marionette_ar/tracking/camera_model.hpp"

namespace marionette::ar {

struct PlanarFeature {
  float x = 0, y = 0;  // keyframe pixels
  float size = 0, angle = 0, response = 0;
  std::int32_t octave = 0;
  std::array<std::uint8_t, 32> descriptor{};  // ORB, 256 bits
};

struct PlanarKeyframe {
  int width = 0, height = 0;
  std::vector<std::uint8_t> grey;          // width * height, rows top to bottom
  std::array<double, 9> planeToImage{};    // row-major 3x3: (X, Z, 1) -> keyframe pixel (homogeneous)
  std::vector<std::array<float, 2>> corners;  // pixels, strongest first
  std::vector<PlanarFeature> features;
};

struct PlanarMap {
  static constexpr std::uint32_t kVersion = 1;
  static constexpr int kMaxKeyframes = 64;
  static constexpr int kMaxKeyframeSide = 4096;
  static constexpr int kMaxPointsPerKeyframe = 20000;

  CameraModel camera;  // the camera the map was built for (a reference keyframe needs none)
  double targetWidth = 0, targetHeight = 0;  // metres
  std::vector<PlanarKeyframe> keyframes;
  // The file's own CRC-32 (its last 4 bytes) when read: what an augmentation names the map by
  // (docs/authoring.md). Not written: the writer computes it.
  std::uint32_t checksum = 0;
};

// Writes `map` to `file`; false with an error in `diagnostics` naming the file if it cannot.
[[nodiscard]] bool writePlanarMap(const std::string& file, const PlanarMap& map, Diagnostics& diagnostics);
// Reads a map. Errors name the file and the place: not a map, another version, truncated,
// a count past the limits or the bytes left, a checksum mismatch, a camera with a problem().
[[nodiscard]] std::optional<PlanarMap> readPlanarMap(const std::string& file, Diagnostics& diagnostics);
// The same from bytes in memory (the fuzz target's entry); `name` names them in errors.
[[nodiscard]] std::optional<PlanarMap> parsePlanarMap(const std::uint8_t* data, std::size_t size,
                                                      const std::string& name, Diagnostics& diagnostics);

}  // namespace marionette::ar
