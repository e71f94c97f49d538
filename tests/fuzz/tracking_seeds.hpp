// Valid tracking inputs the fuzz targets and the mutation test start from, written here (not
// copied from anywhere): small planar maps and camera calibrations in YAML, XML and JSON.
#pragma once
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "marionette_ar/tracking/planar_map.hpp"

namespace marionette::fuzz {

inline ar::PlanarKeyframe seedKeyframe(int width, int height, int points) {
  ar::PlanarKeyframe k;
  k.width = width;
  k.height = height;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) k.grey.push_back(static_cast<std::uint8_t>((x * 16 + y * 5) & 0xff));
  k.planeToImage = {80, 0, 8, 0, 80, 8, 0, 0, 1};  // a 0.2 m target over 16 pixels, centred
  for (int i = 0; i < points; ++i) {
    k.corners.push_back({2.5f + 4.0f * static_cast<float>(i), 3.0f + 3.5f * static_cast<float>(i)});
    ar::PlanarFeature f;
    f.x = 4.0f + 3.0f * static_cast<float>(i);
    f.y = 5.0f + 2.0f * static_cast<float>(i);
    f.size = 31;
    f.angle = 45.0f * static_cast<float>(i);
    f.response = 0.001f;
    f.octave = i;
    for (std::size_t b = 0; b < f.descriptor.size(); ++b) f.descriptor[b] = static_cast<std::uint8_t>(b * 7 + i);
    k.features.push_back(f);
  }
  return k;
}

inline ar::PlanarMap seedPlanarMap(int keyframes) {
  ar::PlanarMap m;
  m.camera.width = 64;
  m.camera.height = 48;
  m.camera.fx = m.camera.fy = 50;
  m.camera.cx = 31.5;
  m.camera.cy = 23.5;
  m.camera.distortion = {-0.1, 0.01, 0, 0, 0};
  m.targetWidth = m.targetHeight = 0.2;
  m.keyframes.push_back(seedKeyframe(16, 16, 2));
  if (keyframes > 1) m.keyframes.push_back(seedKeyframe(20, 16, 0));
  return m;
}

// Written here, not copied: the fields and layout of OpenCV's calibration samples.
inline constexpr const char* kSeedCalibrations[][2] = {
    {"calibration.yml", R"(%YAML:1.0
---
nframes: 13
image_width: 640
image_height: 480
board_width: 9
board_height: 6
square_size: 2.5e-02
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 6.0e+02, 0., 3.195e+02, 0.,
       6.1e+02, 2.395e+02, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 5
   cols: 1
   dt: d
   data: [ -2.0e-01, 5.0e-02,
       1.0e-03, -2.0e-03,
       1.0e-02 ]
avg_reprojection_error: 3.9e-01
)"},
    {"calibration.xml", R"(<?xml version="1.0"?>
<opencv_storage>
<image_width>320</image_width>
<image_height>240</image_height>
<camera_matrix type_id="opencv-matrix">
  <rows>3</rows>
  <cols>3</cols>
  <dt>f</dt>
  <data>
    300. 0. 159.5 0. 300. 119.5 0. 0. 1.</data></camera_matrix>
<distortion_coefficients type_id="opencv-matrix">
  <rows>1</rows>
  <cols>4</cols>
  <dt>f</dt>
  <data>
    -0.1 0.02 0. 0.</data></distortion_coefficients>
</opencv_storage>
)"},
    {"calibration.json", R"({
    "image_width": 1280,
    "image_height": 720,
    "camera_matrix": {
        "type_id": "opencv-matrix",
        "rows": 3,
        "cols": 3,
        "dt": "d",
        "data": [ 900.0, 0.0, 639.5, 0.0, 900.0, 359.5, 0.0, 0.0, 1.0 ]
    },
    "distortion_coefficients": {
        "type_id": "opencv-matrix",
        "rows": 8,
        "cols": 1,
        "dt": "d",
        "data": [ 0.1, -0.05, 0.0, 0.0, 0.01, 0.0, 0.0, 0.0 ]
    }
}
)"},
};

// `bytes` with its last 4 bytes made the CRC-32 of the rest, as a planar map's trailer.
inline void patchMapChecksum(std::uint8_t* bytes, std::size_t size) {
  if (size < 4) return;
  const auto sum = static_cast<std::uint32_t>(crc32(0L, bytes, static_cast<uInt>(size - 4)));
  std::memcpy(bytes + size - 4, &sum, 4);
}

}  // namespace marionette::fuzz
