// A live camera as a background source: a V4L2 device (an index or a /dev/video* path) or a
// stream URL (FFmpeg: rtsp://, http://, udp://, file://...), read by OpenCV's VideoCapture.
//
// A live source has no time axis: frameAt() ignores the scene time and returns the newest frame
// the camera has delivered. A capture thread of the source's own grabs and retrieves frames as
// fast as the camera gives them (which also keeps the driver's queue empty, so the newest frame
// is never one that waited in it) and converts each to RGB8 into one of three buffers it rotates
// with the renderer's thread under a mutex: frameAt() never waits for the camera unless asked
// to, and no buffer is allocated after the first frame (cv::cvtColor writes into the buffer).
//
// - waitForNewFrame false (a window): frameAt() takes the newest frame if one arrived since the
//   last call, else returns the same frame again (same `index`): it never blocks.
// - waitForNewFrame true (marionette-ar --headless, which renders at a fixed fps as fast as it
//   can): frameAt() waits up to timeoutSeconds for a frame newer than the one shown last, so
//   no camera frame is written twice; frames the renderer is too slow for are skipped, as in
//   a window. The scene clock still steps at the scene's fps: the output is not the camera's
//   timing.
//
// `index` counts the frames captured (0, 1, ...): it changes exactly when the pixels do.
// Errors name the device: "camera 0 (/dev/video0): no such device", "... cannot open ...",
// "... no frame within 5 s". The device is opened in the capture thread, so an open that
// blocks (a stream that never answers, a FIFO nobody writes) is bounded by the timeout too.
// When the camera stops delivering (unplugged, the stream ends: grab() fails), frameAt()
// reports it once as an error in its diagnostics and keeps returning the last frame; it does
// not reconnect. Frames of another size than the first are dropped (reported once).
#pragma once
#include <memory>
#include <string>

#include "marionette_ar/background_source.hpp"

namespace marionette::ar {

struct LiveCameraSettings {
  int index = -1;      // >= 0: /dev/video<index> through V4L2
  std::string device;  // else: a /dev/ path (V4L2) or a URL with "://" (FFmpeg)
  int width = 0, height = 0;  // a capture size to ask the device for (0: its default)
  double timeoutSeconds = 5;  // for the first frame, and for each frame when waitForNewFrame
  bool waitForNewFrame = false;
};

// How errors name the camera: "camera 0 (/dev/video0)", or the device / URL.
[[nodiscard]] std::string liveCameraName(const LiveCameraSettings& settings);

// Opens the camera and waits for its first frame (up to timeoutSeconds). nullptr with an
// error naming the device when it does not exist, cannot be opened, or gives no frame in time.
// The source's fps() is 0 and frameCount() 0 (no time axis, no end).
[[nodiscard]] std::unique_ptr<BackgroundSource> openLiveCamera(const LiveCameraSettings& settings,
                                                               Diagnostics& diagnostics);

}  // namespace marionette::ar
