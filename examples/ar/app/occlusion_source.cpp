#include "occlusion_source.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>

#if MARIONETTE_AR_HAS_TRACKING
#include "marionette_ar/tracking/target_occlusion.hpp"
#include "tracked_camera.hpp"
#endif

namespace marionette::ar {

std::unique_ptr<OcclusionSource> OcclusionSource::create(const ArScene& scene, Diagnostics& diagnostics) {
  const ArOcclusion& settings = scene.occlusion;
  if (!settings.enabled) return nullptr;
  std::unique_ptr<OcclusionSource> source(new OcclusionSource());
  if (!settings.masks.empty()) {
    namespace fs = std::filesystem;
    std::error_code error;
    if (!fs::is_directory(settings.masks, error)) {
      diagnostics.error(scene.path, "render.occlusion.masks: '" + settings.masks + "' is not a folder");
      return nullptr;
    }
    for (const auto& entry : fs::directory_iterator(settings.masks, error)) {
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
      if (entry.is_regular_file() && (ext == ".png" || ext == ".pgm" || ext == ".jpg" || ext == ".bmp" || ext == ".tif"))
        source->files_.push_back(entry.path().string());
    }
    std::sort(source->files_.begin(), source->files_.end());
    if (source->files_.empty()) {
      diagnostics.error(scene.path, "render.occlusion.masks: '" + settings.masks + "' holds no image");
      return nullptr;
    }
    return source;
  }
  if (scene.camera.tracker.kind == ArTracker::Kind::Markerless) return source;
  if (settings.asked)
    diagnostics.warning(scene.path,
                        scene.camera.tracker.kind == ArTracker::Kind::AprilTag
                            ? "render.occlusion: the AprilTag tracker has no image of its target to find what hides "
                              "it; occlusion over the target is off"
                            : "render.occlusion: only a markerless tracker (or \"masks\") says what hides the "
                              "target; occlusion over the target is off");
  return nullptr;
}

bool OcclusionSource::frame(std::int64_t frameIndex, TrackedCamera* tracked, OcclusionFrame& out,
                            Diagnostics& diagnostics) {
  const auto start = std::chrono::steady_clock::now();
  bool have = false;
  if (!files_.empty()) {
    if (frameIndex >= 0 && std::size_t(frameIndex) < files_.size()) {
      if (frameIndex != loaded_) {
        loaded_ = frameIndex;
        grey_.clear();
        if (readImage(files_[std::size_t(frameIndex)], image_, diagnostics) && image_.channels > 0) {
          const std::size_t n = std::size_t(image_.width) * std::size_t(image_.height);
          grey_.resize(n);
          double sum = 0.0;
          for (std::size_t i = 0; i < n; ++i) {  // the first channel (a grey file's value)
            grey_[i] = image_.pixels[i * std::size_t(image_.channels)];
            sum += grey_[i];
          }
          hiddenShare_ = n ? sum / (255.0 * double(n)) : 0.0;
        }
      }
      if (!grey_.empty()) {
        out.pixels = grey_.data();
        out.width = image_.width;
        out.height = image_.height;
        out.stride = image_.width;
        out.imageToMask = glm::vec2(1.0f);
        out.hiddenShare = hiddenShare_;
        have = true;
      }
    }
  }
#if MARIONETTE_AR_HAS_TRACKING
  else if (tracked) {
    if (const OcclusionMask* m = tracked->occlusionMask(); m && m->targetInView && m->pixels) {
      out.pixels = m->pixels;
      out.width = m->width;
      out.height = m->height;
      out.stride = m->width;
      // Mask pixel u covers frame pixels [scale u, scale u + scale): the last may pass the frame's edge.
      const CameraModel& camera = tracked->camera();
      out.imageToMask = glm::vec2(float(camera.width) / float(m->scale * m->width),
                                  float(camera.height) / float(m->scale * m->height));
      out.hiddenShare = m->hiddenShare;
      have = true;
    }
  }
#else
  (void)tracked;
#endif
  ms_ += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  ++frames_;
  return have;
}

}  // namespace marionette::ar
