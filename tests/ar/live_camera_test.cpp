// The live camera background (marionette_ar/live_camera.hpp). This machine has no camera, so:
// the error paths are tested on what exists (no /dev/video99, an index with no device,
// /dev/null which is no capture device, a FIFO nobody writes: an open that blocks, bounded by
// the timeout); the capture thread, the newest-frame hand-over and a source that stops are
// tested on a video file opened as a stream URL (file://, FFmpeg): it delivers frames as fast
// as it decodes them, then its grab fails as an unplugged camera's does. The V4L2 capture of
// a real device is not exercised here.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include "marionette_ar/live_camera.hpp"

using namespace marionette::ar;
using marionette::Diagnostics;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Large enough frames, and enough of them, that decoding the stream takes a while (a
// few hundred ms here), so that the reader sees it running.
constexpr int kW = 640, kH = 480, kFrames = 200;

fs::path tempDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("marionette_live_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Frame k is a flat colour: red 6 (k mod 40), blue 40 (k div 40) (MJPG keeps flat colours
// within a few levels).
std::string writeVideo(const fs::path& dir) {
  const std::string path = (dir / "stream.avi").string();
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30, cv::Size(kW, kH));
  EXPECT_TRUE(writer.isOpened());
  for (int k = 0; k < kFrames; ++k) writer.write(cv::Mat(kH, kW, CV_8UC3, cv::Scalar(40 * (k / 40), 128, 6 * (k % 40))));
  return path;
}

int number(const BackgroundFrame& f) {
  const std::uint8_t* p = &f.rgb[((f.height / 2) * f.width + f.width / 2) * 3];
  return (p[0] + 3) / 6 + 40 * ((p[2] + 20) / 40);
}

double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string openError(const LiveCameraSettings& s) {
  Diagnostics d;
  const auto start = Clock::now();
  EXPECT_EQ(openLiveCamera(s, d), nullptr);
  EXPECT_LT(secondsSince(start), s.timeoutSeconds + 2.0) << "the open was not bounded by the timeout";
  return d.format();
}

}  // namespace

TEST(LiveCamera, MissingAndWrongDevicesAreNamed) {
  LiveCameraSettings s;
  s.device = "/dev/video99";
  EXPECT_EQ(openError(s), "/dev/video99: error: no such device\n");
  s = {};
  s.index = 42;
  EXPECT_EQ(openError(s), "camera 42 (/dev/video42): error: no such device\n");
  s = {};
  s.device = "/dev/null";  // exists, but is no V4L2 capture device
  const std::string notCamera = openError(s);
  EXPECT_NE(notCamera.find("/dev/null: error: cannot open it as a V4L2 capture device"), std::string::npos) << notCamera;
  s = {};
  s.device = "camera.mp4";
  EXPECT_NE(openError(s).find("a device index, a /dev/ path or a stream URL"), std::string::npos);
  s = {};
  s.device = "file:///nonexistent/stream.avi";
  EXPECT_NE(openError(s).find("file:///nonexistent/stream.avi: error: OpenCV (FFmpeg) cannot open the stream"),
            std::string::npos);
}

TEST(LiveCamera, AStreamThatNeverAnswersTimesOut) {
  const fs::path dir = tempDir("fifo");
  const std::string fifo = (dir / "silent").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  LiveCameraSettings s;
  s.device = "file://" + fifo;  // opening a FIFO for reading blocks until someone writes
  s.timeoutSeconds = 0.5;
  EXPECT_EQ(openError(s), s.device + ": error: no frame within 0.5 s\n");
  // Let the abandoned open return (it then reads end-of-file and the thread ends).
  const int fd = ::open(fifo.c_str(), O_WRONLY);
  ASSERT_GE(fd, 0);
  ::close(fd);
}

TEST(LiveCamera, AStreamGivesItsNewestFramesThenKeepsTheLastOne) {
  const std::string url = "file://" + writeVideo(tempDir("stream"));
  for (const bool wait : {true, false}) {
    SCOPED_TRACE(wait ? "offline: waits for a new frame" : "windowed: never waits");
    LiveCameraSettings s;
    s.device = url;
    s.timeoutSeconds = 2;
    s.waitForNewFrame = wait;
    Diagnostics d;
    const auto source = openLiveCamera(s, d);
    ASSERT_TRUE(source) << d.format();
    EXPECT_EQ(source->width(), kW);
    EXPECT_EQ(source->height(), kH);
    EXPECT_EQ(source->fps(), 0.0);  // no time axis
    std::int64_t lastIndex = -1;
    int lastNumber = -1, distinct = 0, calls = 0;
    double slowest = 0;
    const auto start = Clock::now();
    // Until the stream has ended and reported it (once), and a few calls more.
    for (int after = 0; after < 5 && secondsSince(start) < 20; ++calls) {
      Diagnostics fd;
      const auto t0 = Clock::now();
      const BackgroundFrame& f = source->frameAt(-1.0 * calls, fd);  // the time is ignored
      slowest = std::max(slowest, secondsSince(t0));
      ASSERT_EQ(f.width, kW);
      ASSERT_GE(f.index, lastIndex) << "an older frame came back";
      const int k = number(f);
      ASSERT_GE(k, lastNumber) << "an older frame came back";
      ASSERT_LT(k, kFrames);
      if (f.index != lastIndex) ++distinct;
      else EXPECT_EQ(k, lastNumber) << "the index stayed but the pixels changed";
      if (wait && after == 0 && fd.ok()) {
        EXPECT_NE(f.index, lastIndex) << "offline, every call gives a new frame";
      }
      lastIndex = f.index;
      lastNumber = k;
      if (!fd.ok() || after > 0) {
        if (after == 0) {
          EXPECT_NE(fd.format().find(url + ": error: stopped delivering frames after " + std::to_string(kFrames)),
                    std::string::npos) << fd.format();
          EXPECT_NE(fd.format().find("the last frame stays"), std::string::npos);
        } else {
          EXPECT_TRUE(fd.ok()) << "reported twice: " << fd.format();
        }
        ++after;
      }
      if (!wait) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    EXPECT_EQ(lastNumber, kFrames - 1) << "the last frame stays";
    EXPECT_EQ(lastIndex, kFrames - 1);
    EXPECT_GE(distinct, 2);
    if (wait) EXPECT_LT(slowest, 2.5);
    else EXPECT_LT(slowest, 0.05) << "a windowed frame waited for the camera";
    std::printf("%s: %d calls, %d distinct frames of %d, slowest call %.1f ms\n", wait ? "offline" : "windowed", calls,
                distinct, kFrames, 1000 * slowest);
  }
}
