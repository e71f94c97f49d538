// Pyramidal Lucas-Kanade point tracking (Bouguet's formulation, as cv::calcOpticalFlowPyrLK
// with OPTFLOW_USE_INITIAL_FLOW) over image pyramids whose levels are allocated once: the
// markerless tracker's per-frame KLT without OpenCV's per-call pyramids and scratch images.
// Its arithmetic is OpenCV's fixed point (samples with 5 fractional bits, 14-bit bilinear
// weights, 16-bit multiply-adds): 1.6 times as fast as the float loops it replaced, the same
// bits with SSE2 or without (docs/benchmarks.md, Tracking/KltOwn).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <opencv2/core.hpp>

namespace marionette::ar {

// One level of a grey 8-bit image (not owned).
struct GreyLevel {
  const std::uint8_t* data = nullptr;
  int width = 0, height = 0;
  std::ptrdiff_t stride = 0;  // bytes from one row to the next
  [[nodiscard]] const std::uint8_t* row(int y) const noexcept { return data + y * stride; }
};

// Level 0 is the caller's image (viewed, not copied); level l + 1 is level l smoothed by the
// 5-tap Gaussian [1 4 6 4 1] / 16 in x and y and decimated by 2, border reflect-101 and sizes
// ((w + 1) / 2, (h + 1) / 2): cv::pyrDown, to the bit.
class ImagePyramid {
 public:
  static constexpr int kMaxLevels = 8;

  // Buffers for `levels` levels above a width x height level 0. Allocates (the only call that
  // does); false for a size < 1 or levels outside 0..kMaxLevels. `wide`: AVX2 where the CPU
  // has it (the same bits; false for the scalar loops, which the tests compare it with).
  bool configure(int width, int height, int levels, bool wide = true);
  // Every configured level from `image` (CV_8UC1 of the configured size; it must stay alive
  // and unchanged while the pyramid is used). False otherwise (the pyramid then has no level).
  bool build(const cv::Mat& image) noexcept;
  // Only what `region` of level 0 needs: level l + 1 gets the pixels over level l's part (its
  // box halved, rounded outwards and grown by one pixel), the rest of the level is `outside`.
  // Exact inside the region, away from its border by a few pixels per level, for an image that
  // is `outside` around the region (the tracker's template): a fraction of the work of build().
  bool buildRegion(const cv::Mat& image, cv::Rect region, std::uint8_t outside) noexcept;

  [[nodiscard]] int levels() const noexcept { return built_; }  // levels above 0 built
  [[nodiscard]] const GreyLevel& level(int l) const noexcept { return views_[static_cast<std::size_t>(l)]; }
  // The level's pixels as a cv::Mat header (no copy, no allocation: the data is not owned).
  [[nodiscard]] cv::Mat levelMat(int l) const noexcept;

 private:
  int width_ = 0, height_ = 0, configured_ = 0, built_ = 0;
  bool wide_ = true;
  std::array<GreyLevel, kMaxLevels + 1> views_{};
  std::array<std::vector<std::uint8_t>, kMaxLevels> storage_;  // levels 1..
  std::vector<std::uint16_t> columnSums_;                       // one row of vertical sums (at most 16 x 255)

  bool start(const cv::Mat& image) noexcept;
  void downsample(int level, cv::Rect dstRegion) noexcept;  // level - 1 -> level over dstRegion
};

// The loops a track() call runs: the portable ones, SSE2 or AVX2 (all give the same bits).
enum class LkKernels { Portable, Sse2, Avx2 };

// How the template's gradient is taken: OpenCV's 3x3 Scharr (cv::calcOpticalFlowPyrLK), or
// the central difference (tracking_primitives_test measures both: a wash).
enum class LkGradient { Scharr, Central };

struct LucasKanadeOptions {
  int window = 15;              // side in pixels, odd, 3..LucasKanade::kMaxWindow
  int coarseWindow = 0;         // the side above level 0 (0: `window`); a smear shrinks there
  int levels = 3;               // pyramid levels above full resolution
  int maxIterations = 20;       // per level
  double epsilon = 0.01;        // stop when a step is shorter than this (pixels)
  double minEigThreshold = 1e-4;  // OpenCV's units: min eigenvalue / (window area * 1024)
  LkGradient gradient = LkGradient::Scharr;
  // SSE2 where the machine has it; false: the portable loops, which give the same bits (the
  // arithmetic is integer: tracking_primitives_test compares them).
  bool simd = true;
  // With `simd`: AVX2 where the CPU has it (sixteen lanes, the same bits again); false: SSE2.
  bool wide = true;
};

class LucasKanade {
 public:
  static constexpr int kMaxWindow = 61;
  LucasKanade();  // sizes the patch buffers for kMaxWindow (allocates)

  // Finds in `frame` the points `from` of `templ` (level-0 pixels), starting from the guesses
  // in `to` and writing the results there. status[i] = 1 when found; 0 when the point's window
  // leaves the image, the window's gradient matrix has too small an eigenvalue (no texture, or
  // an edge), or a coordinate is not finite. Levels used: the fewest of params.levels, either
  // pyramid's and those wider and taller than the window. The pyramids must have the same
  // level-0 size (else 0, every status 0). Returns the number found. Allocates nothing.
  int track(const ImagePyramid& templ, const ImagePyramid& frame, std::span<const cv::Point2f> from,
            std::span<cv::Point2f> to, std::span<std::uint8_t> status, const LucasKanadeOptions& params) noexcept;

 private:
  // Per point and level, in fixed point (lucas_kanade.cpp): the template's samples
  // (window + 2)^2, and over the window its values, gradients and the frame's samples, rows
  // padded to a multiple of 8 lanes; a reflect-101 copy of the pixels near a border.
  std::vector<std::int16_t> patch_, values_, gx_, gy_, samples_;
  std::vector<std::uint8_t> border_;

  void sample(const GreyLevel& img, int x, int y, float ax, float ay, int cols8, int rows, std::int16_t* out,
              LkKernels kernels) noexcept;
  bool trackOne(const GreyLevel& t, const GreyLevel& f, cv::Point2f prev, cv::Point2f& next, int window,
                const LucasKanadeOptions& params, LkKernels kernels) noexcept;
};

}  // namespace marionette::ar
