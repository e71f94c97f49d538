#include "marionette_ar/live_camera.hpp"

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

namespace marionette::ar {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string seconds(double s) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", s);
  return b;
}

// What the capture thread and the renderer's thread share (the thread keeps it alive: it may
// outlive the source when a blocked open or read is abandoned).
struct Shared {
  std::mutex mutex;
  std::condition_variable changed;
  BackgroundFrame ready;       // the newest frame, index -1 until the first
  bool failed = false;         // the thread has ended on an error
  std::string failure;         // what went wrong
  bool sizeChanged = false;    // frames of another size were dropped
  bool stop = false, finished = false;
};

bool openCapture(cv::VideoCapture& capture, const LiveCameraSettings& s, const std::string& path) {
  const int timeoutMs = static_cast<int>(std::min(1e6, s.timeoutSeconds * 1000.0));
  bool ok = false;
  try {
    if (s.index >= 0) ok = capture.open(s.index, cv::CAP_V4L2);
    else if (path.rfind("/dev/", 0) == 0) ok = capture.open(path, cv::CAP_V4L2);
    else
      ok = capture.open(path, cv::CAP_FFMPEG,
                        {cv::CAP_PROP_OPEN_TIMEOUT_MSEC, timeoutMs, cv::CAP_PROP_READ_TIMEOUT_MSEC, timeoutMs});
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (ok && s.width > 0 && s.height > 0) {
    capture.set(cv::CAP_PROP_FRAME_WIDTH, s.width);
    capture.set(cv::CAP_PROP_FRAME_HEIGHT, s.height);
  }
  return ok && capture.isOpened();
}

void captureLoop(std::shared_ptr<Shared> shared, LiveCameraSettings settings, std::string path) {
  cv::VideoCapture capture;
  auto end = [&](const std::string& why) {
    std::lock_guard<std::mutex> lock(shared->mutex);
    if (!why.empty()) {
      shared->failed = true;
      shared->failure = why;
    }
    shared->finished = true;
    shared->changed.notify_all();
  };
  if (!openCapture(capture, settings, path)) {
    end(settings.index >= 0 || path.rfind("/dev/", 0) == 0
            ? "cannot open it as a V4L2 capture device (busy, no permission, or not a camera)"
            : "OpenCV (FFmpeg) cannot open the stream");
    return;
  }
  BackgroundFrame back;  // filled here, then swapped with shared->ready
  cv::Mat bgr;
  std::int64_t captured = 0;
  try {
    while (true) {
      {
        std::lock_guard<std::mutex> lock(shared->mutex);
        if (shared->stop) break;
      }
      if (!capture.grab() || !capture.retrieve(bgr) || bgr.empty() || bgr.depth() != CV_8U) {
        end(captured == 0 ? "opened, but gives no frame (grab failed)" : "stopped delivering frames after " +
                                                                               std::to_string(captured) + " (grab failed)");
        return;
      }
      if (captured == 0) {
        back.width = bgr.cols;
        back.height = bgr.rows;
        back.rgb.resize(static_cast<std::size_t>(bgr.cols) * bgr.rows * 3);
      } else if (bgr.cols != back.width || bgr.rows != back.height) {
        std::lock_guard<std::mutex> lock(shared->mutex);
        shared->sizeChanged = true;
        continue;
      }
      cv::Mat rgb(back.height, back.width, CV_8UC3, back.rgb.data());  // converted in place
      const int code = bgr.channels() == 1 ? cv::COLOR_GRAY2RGB : bgr.channels() == 4 ? cv::COLOR_BGRA2RGB : cv::COLOR_BGR2RGB;
      cv::cvtColor(bgr, rgb, code);
      back.index = captured++;
      std::lock_guard<std::mutex> lock(shared->mutex);
      // The three buffers (this one, ready, the renderer's) have one size: a swap allocates nothing.
      if (shared->ready.rgb.size() != back.rgb.size()) shared->ready.rgb.resize(back.rgb.size());
      std::swap(back, shared->ready);
      if (back.rgb.size() != shared->ready.rgb.size()) back.rgb.resize(shared->ready.rgb.size());
      back.width = shared->ready.width;
      back.height = shared->ready.height;
      shared->changed.notify_all();
    }
  } catch (const cv::Exception& e) {
    end(std::string("OpenCV failed reading it: ") + e.what());
    return;
  }
  end("");
}

class LiveCameraSource final : public BackgroundSource {
 public:
  LiveCameraSource(LiveCameraSettings settings, std::string name)
      : settings_(std::move(settings)), name_(std::move(name)), shared_(std::make_shared<Shared>()) {}

  ~LiveCameraSource() override {
    if (!thread_.joinable()) return;
    std::unique_lock<std::mutex> lock(shared_->mutex);
    shared_->stop = true;
    // A grab returns within a frame period; one stuck in a dead device or stream is abandoned
    // (the thread owns what it uses) rather than hanging the renderer's exit.
    const bool done = shared_->changed.wait_for(lock, std::chrono::seconds(2), [&] { return shared_->finished; });
    lock.unlock();
    if (done) thread_.join();
    else thread_.detach();
  }

  bool open(Diagnostics& d) {
    const std::string path = settings_.index >= 0 ? "/dev/video" + std::to_string(settings_.index) : settings_.device;
    std::error_code ec;
    if (path.rfind("/dev/", 0) == 0 && !fs::exists(path, ec)) {
      d.error(name_, "no such device");
      return false;
    }
    thread_ = std::thread(captureLoop, shared_, settings_, path);
    std::unique_lock<std::mutex> lock(shared_->mutex);
    const auto timeout = std::chrono::duration<double>(settings_.timeoutSeconds);
    if (!shared_->changed.wait_for(lock, timeout, [&] { return shared_->ready.index >= 0 || shared_->failed; })) {
      shared_->stop = true;
      lock.unlock();
      thread_.detach();  // an open or a read that blocks is abandoned, not waited for
      d.error(name_, "no frame within " + seconds(settings_.timeoutSeconds) + " s");
      return false;
    }
    if (shared_->ready.index < 0) {
      const std::string why = shared_->failure;
      lock.unlock();
      thread_.join();
      d.error(name_, why);
      return false;
    }
    take();
    return true;
  }

  const BackgroundFrame& frameAt(double, Diagnostics& d) override {
    std::unique_lock<std::mutex> lock(shared_->mutex);
    const auto fresh = [&] { return shared_->ready.index > front_.index || shared_->failed; };
    if (settings_.waitForNewFrame && !fresh()) {
      if (!shared_->changed.wait_for(lock, std::chrono::duration<double>(settings_.timeoutSeconds), fresh) &&
          !reportedSlow_) {
        reportedSlow_ = true;
        d.error(name_, "no new frame within " + seconds(settings_.timeoutSeconds) + " s; the last frame stays");
      }
    }
    if (shared_->ready.index > front_.index) take();
    if (shared_->failed && !reportedFailure_) {
      reportedFailure_ = true;
      d.error(name_, shared_->failure + "; the last frame stays");
    }
    if (shared_->sizeChanged && !reportedSize_) {
      reportedSize_ = true;
      d.error(name_, "frames changed size from " + std::to_string(front_.width) + "x" + std::to_string(front_.height) +
                         ": they are dropped");
    }
    return front_;
  }

  int width() const noexcept override { return front_.width; }
  int height() const noexcept override { return front_.height; }
  double fps() const noexcept override { return 0.0; }
  std::int64_t frameCount() const noexcept override { return 0; }
  std::int64_t decodedFrames() const noexcept override { return front_.index + 1; }

 private:
  void take() {  // with the mutex held
    // `ready` gets the older frame's buffer; its index is below front_'s, so it is not taken
    // again until the thread publishes a newer frame into it.
    std::swap(front_, shared_->ready);
  }

  LiveCameraSettings settings_;
  std::string name_;
  std::shared_ptr<Shared> shared_;
  std::thread thread_;
  BackgroundFrame front_;
  bool reportedFailure_ = false, reportedSlow_ = false, reportedSize_ = false;
};

}  // namespace

std::string liveCameraName(const LiveCameraSettings& s) {
  if (s.index >= 0) return "camera " + std::to_string(s.index) + " (/dev/video" + std::to_string(s.index) + ")";
  return s.device;
}

std::unique_ptr<BackgroundSource> openLiveCamera(const LiveCameraSettings& settings, Diagnostics& d) {
  const std::string name = liveCameraName(settings);
  if (settings.index < 0 && settings.device.rfind("/dev/", 0) != 0 && settings.device.find("://") == std::string::npos) {
    d.error(name.empty() ? "camera" : name,
            "a camera is a device index, a /dev/ path or a stream URL (scheme://...)");
    return nullptr;
  }
  if (!(settings.timeoutSeconds > 0) || settings.timeoutSeconds > 3600) {
    d.error(name, "the camera's timeout must be in (0, 3600] s");
    return nullptr;
  }
  auto source = std::make_unique<LiveCameraSource>(settings, name);
  if (!source->open(d)) return nullptr;
  return source;
}

}  // namespace marionette::ar
