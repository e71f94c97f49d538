// Where the occlusion mask of each camera frame comes from (docs/ar-renderer.md, "Occlusion over
// the target"): the markerless tracker's (marionette_ar/tracking/target_occlusion.hpp), or a
// folder of masks made elsewhere ("render": {"occlusion": {"masks": "dir"}}: a segmentation, or
// the tests' truth). Off, with a warning when the scene asked for it, where there is neither.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ar_scene_file.hpp"
#include "marionette_ar/render/image.hpp"

namespace marionette::ar {

class TrackedCamera;

// One frame's mask: 255 where something real hides the target, rows top to bottom.
struct OcclusionFrame {
  const std::uint8_t* pixels = nullptr;
  int width = 0, height = 0;
  std::ptrdiff_t stride = 0;
  glm::vec2 imageToMask{1.0f, 1.0f};  // frame uv -> mask texture coordinates
  double hiddenShare = 0.0;           // of the target (the tracker's), of the frame (a folder's)
  int frameWidth = 0, frameHeight = 0;  // the camera frame it belongs to
};

class OcclusionSource {
 public:
  // Null when occlusion is off, or when the camera gives no mask (a warning naming the scene key
  // if the file asked for it); a "masks" folder that is missing or holds no image is an error.
  [[nodiscard]] static std::unique_ptr<OcclusionSource> create(const ArScene& scene, Diagnostics& diagnostics);

  // The mask of background frame `frameIndex` (`tracked`: the markerless tracker that saw it).
  // False when there is none for this frame (no pose, no file); a file that cannot be read is a
  // warning in `diagnostics`, naming it. The tracker's mask is made on the calling thread and
  // allocates nothing; a folder's is read from disk.
  [[nodiscard]] bool frame(std::int64_t frameIndex, TrackedCamera* tracked, OcclusionFrame& out,
                           Diagnostics& diagnostics);
  // Mean time of frame() per frame asked, ms.
  [[nodiscard]] double meanMilliseconds() const noexcept { return frames_ ? ms_ / double(frames_) : 0.0; }

 private:
  std::vector<std::string> files_;  // the "masks" folder's images, in name order
  Image8 image_;
  std::vector<std::uint8_t> grey_;  // its first channel
  double hiddenShare_ = 0.0;
  std::int64_t loaded_ = -1;
  double ms_ = 0.0;
  long frames_ = 0;
};

}  // namespace marionette::ar
