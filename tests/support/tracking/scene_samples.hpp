// The synthetic renderer's scene samples (the target and the floor through the lens, without
// hand planes), four at a time with AVX2: the same bits as SequenceRenderer::sceneSample's
// scalar loop, which the test frames of every tracking test come from (docs/testing.md:
// rendering took most of the default configuration's tracking tests).
#pragma once

#include <cstddef>

#include <opencv2/core.hpp>

namespace marionette::ar::synthetic {

// One pyramid level of a texture, RGB and a channel never read: CV_32FC4 (16 bytes a texel),
// or CV_8UC4 (4 bytes) where every value of the level is a whole number 0-255, as a level made
// from an 8-bit image is (the same values, a quarter of the memory traffic).
struct SampleLevel {
  const unsigned char* data = nullptr;
  std::ptrdiff_t step = 0;  // bytes a row
  int cols = 0, rows = 0;
  int texelBytes = 16;  // 16: float texels; 4: byte texels
};

// A texture pyramid as fetchFiltered reads it: `wrap` tiles (else edges replicate); past the
// last level it fades into `mean` over `fade` levels.
struct SampleTexture {
  const SampleLevel* levels = nullptr;
  int count = 0;
  cv::Vec3f mean;
  bool wrap = false;
  int fade = 0;
};

// Everything sceneSample reads for one view: the rays, the planes' mappings, the textures.
struct SampleSource {
  // Rays per supersample: `rays` (row-major x, y pairs, NaN where the lens has no inverse), or
  // per column and per row for a pinhole.
  const double* rays = nullptr;
  const double* columnRays = nullptr;
  const double* rowRays = nullptr;
  int width = 0, height = 0;  // supersamples
  double toGround[9] = {}, toOccluder[9] = {};  // glm::dmat3 column-major: [column * 3 + row]
  bool groundOk = false;
  double occW = 0, occX0 = 0;  // the flat occluder bar (occW 0: none)
  double targetWidth = 0, targetDepth = 0, texel = 0, floorTexel = 0;
  double targetCols = 0, targetRows = 0;
  double floorPeriodX = 0, floorPeriodZ = 0, floorCols = 0;
  double floorRows = 0;
  bool floorEmpty = false;
  SampleTexture target, floor;
  cv::Vec3f invalidLens, occluder, sky;
};

// Whether sceneSamplesAvx2 is compiled here and the CPU has AVX2.
[[nodiscard]] bool sceneSamplesWideAvailable() noexcept;

// Supersamples (x + stride * i, y) for i < count: writes out[i] for as many as it did, a
// multiple of four (0 where AVX2 is missing); the caller's scalar loop does the rest.
int sceneSamplesAvx2(const SampleSource& s, int x, int stride, int y, int count, cv::Vec3f* out) noexcept;

}  // namespace marionette::ar::synthetic
