// Background sources: a still PNG, a PNG sequence and an MJPG .avi written here, with the
// frame number encoded in the pixel colours.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "marionette_ar/background_source.hpp"

using namespace marionette::ar;
using marionette::Diagnostics;
namespace fs = std::filesystem;

namespace {
constexpr int kW = 64, kH = 48;

fs::path tempDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("marionette_ar_bg_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Frame k: a flat colour (R = 10 k mod 250, G = 255 - R, B = 128), wide steps so that MJPG's
// loss cannot turn one frame into its neighbour.
std::vector<std::uint8_t> framePixels(int k) {
  std::vector<std::uint8_t> px(kW * kH * 3);
  const auto r = static_cast<std::uint8_t>((k * 10) % 250);
  for (int i = 0; i < kW * kH; ++i) px[i * 3] = r, px[i * 3 + 1] = static_cast<std::uint8_t>(255 - r), px[i * 3 + 2] = 128;
  return px;
}
// The frame number a decoded frame shows (from the centre pixel's red), -1 if unclear.
int decodedNumber(const BackgroundFrame& f) {
  const std::uint8_t* p = &f.rgb[((f.height / 2) * f.width + f.width / 2) * 3];
  const int k = (p[0] + 5) / 10;
  if (std::abs(p[0] - k * 10) > 4 || std::abs(p[1] - (255 - k * 10)) > 6 || std::abs(p[2] - 128) > 6) return -1;
  return k;
}

void writePng(const std::string& path, const std::vector<std::uint8_t>& px) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(kW, kH, 3, OIIO::TypeDesc::UINT8)));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
  out->close();
}

std::string writeVideo(const fs::path& dir, int frames, double fps) {
  const std::string path = (dir / "clip.avi").string();
  cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, cv::Size(kW, kH));
  EXPECT_TRUE(writer.isOpened()) << "OpenCV cannot write MJPG here";
  for (int k = 0; k < frames; ++k) {
    const auto px = framePixels(k);
    cv::Mat bgr(kH, kW, CV_8UC3);
    for (int i = 0; i < kW * kH; ++i)
      bgr.data[i * 3] = px[i * 3 + 2], bgr.data[i * 3 + 1] = px[i * 3 + 1], bgr.data[i * 3 + 2] = px[i * 3];
    writer.write(bgr);
  }
  writer.release();
  return path;
}

bool mentions(const Diagnostics& d, const std::string& text) { return d.format().find(text) != std::string::npos; }
}  // namespace

TEST(BackgroundSource, StillPhotoIsOneFrameAtEveryTime) {
  const fs::path dir = tempDir("still");
  const std::string path = (dir / "photo.png").string();
  writePng(path, framePixels(7));
  Diagnostics d;
  auto bg = openBackground(BackgroundKind::Still, path, 0.0, d);
  ASSERT_TRUE(bg) << d.format();
  EXPECT_EQ(bg->width(), kW);
  EXPECT_EQ(bg->height(), kH);
  for (double t : {0.0, 1.5, 1e6}) {
    const BackgroundFrame& f = bg->frameAt(t, d);
    EXPECT_EQ(f.index, 0);
    EXPECT_EQ(f.rgb, framePixels(7));
  }
  EXPECT_TRUE(d.ok());
}

TEST(BackgroundSource, SequenceFromAPatternPicksTheFrameForTheTimeAndLoops) {
  const fs::path dir = tempDir("pattern");
  for (int k = 0; k < 12; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "%04d.png", k + 1);  // numbered from 1
    writePng((dir / name).string(), framePixels(k));
  }
  writePng((dir / "7.png").string(), framePixels(20));  // does not match %04d
  Diagnostics d;
  auto bg = openBackground(BackgroundKind::Sequence, (dir / "%04d.png").string(), 24.0, d);
  ASSERT_TRUE(bg) << d.format();
  EXPECT_EQ(bg->frameCount(), 12);
  for (int k = 0; k < 12; ++k) {
    const BackgroundFrame& f = bg->frameAt(k / 24.0, d);
    EXPECT_EQ(f.index, k);
    EXPECT_EQ(decodedNumber(f), k);
  }
  EXPECT_EQ(bg->decodedFrames(), 12);  // each once, sequentially
  EXPECT_EQ(decodedNumber(bg->frameAt(0.5 - 1e-4, d)), 11);
  EXPECT_EQ(decodedNumber(bg->frameAt(5.5 / 24.0, d)), 5);  // backwards, mid-frame
  EXPECT_EQ(decodedNumber(bg->frameAt(0.5, d)), 0);         // loops: frame 12 is frame 0
  EXPECT_EQ(decodedNumber(bg->frameAt(14.2 / 24.0, d)), 2);
  EXPECT_EQ(bg->frameAt(-3.0, d).index, 0);
  EXPECT_TRUE(d.ok()) << d.format();
}

TEST(BackgroundSource, SequenceFromADirectoryIsSortedByNameAndCanHold) {
  const fs::path dir = tempDir("directory");
  const char* names[] = {"a_shot.png", "b_shot.png", "c_shot.png"};
  for (int k = 0; k < 3; ++k) writePng((dir / names[2 - k]).string(), framePixels(2 - k));
  { std::ofstream(dir / "notes.txt") << "not an image"; }
  Diagnostics d;
  auto bg = openBackground(BackgroundKind::Sequence, dir.string(), 10.0, d, Playback::Hold);
  ASSERT_TRUE(bg) << d.format();
  EXPECT_EQ(bg->frameCount(), 3);
  EXPECT_EQ(decodedNumber(bg->frameAt(0.15, d)), 1);
  EXPECT_EQ(decodedNumber(bg->frameAt(100.0, d)), 2);  // holds the last frame
  EXPECT_EQ(bg->frameAt(100.0, d).index, 2);
}

// `track --images one.png`, a scene's "sequence" of one photo: a single image file is a
// sequence of one frame, shown at every time.
TEST(BackgroundSource, OneImageFileIsAOneFrameSequence) {
  const fs::path dir = tempDir("one_file");
  const std::string path = (dir / "one.png").string();
  writePng(path, framePixels(5));
  writePng((dir / "other.png").string(), framePixels(6));  // the folder's other images are not taken
  for (const Playback playback : {Playback::Loop, Playback::Hold}) {
    Diagnostics d;
    auto bg = openBackground(BackgroundKind::Sequence, path, 30.0, d, playback);
    ASSERT_TRUE(bg) << d.format();
    EXPECT_EQ(bg->frameCount(), 1);
    EXPECT_EQ(bg->width(), kW);
    EXPECT_EQ(bg->height(), kH);
    for (double t : {0.0, 0.5, 100.0}) {
      const BackgroundFrame& f = bg->frameAt(t, d);
      EXPECT_EQ(f.index, 0);
      EXPECT_EQ(decodedNumber(f), 5);
    }
    EXPECT_EQ(bg->decodedFrames(), 1);
    EXPECT_TRUE(d.ok()) << d.format();
  }
  // A file that is not an image is named.
  const std::string text = (dir / "notes.png").string();
  { std::ofstream(text) << "not an image"; }
  Diagnostics d;
  EXPECT_FALSE(openBackground(BackgroundKind::Sequence, text, 30.0, d));
  EXPECT_TRUE(mentions(d, text)) << d.format();
}

TEST(BackgroundSource, VideoFrameByTimeSequentialAndBackwards) {
  const fs::path dir = tempDir("video");
  const double fps = 25.0;
  const std::string path = writeVideo(dir, 20, fps);
  Diagnostics d;
  auto bg = openBackground(BackgroundKind::Video, path, 0.0, d);
  ASSERT_TRUE(bg) << d.format();
  EXPECT_DOUBLE_EQ(bg->fps(), fps);
  EXPECT_EQ(bg->frameCount(), 20);
  EXPECT_EQ(bg->width(), kW);
  // Sequential playback at 50 Hz (each frame shown twice): no re-decoding from the start.
  for (int step = 0; step < 40; ++step) {
    const BackgroundFrame& f = bg->frameAt(step / 50.0, d);
    ASSERT_EQ(f.index, step / 2) << "time " << step / 50.0;
    ASSERT_EQ(decodedNumber(f), step / 2) << "time " << step / 50.0;
  }
  EXPECT_EQ(bg->decodedFrames(), 20);
  // Backwards and forwards jumps.
  for (int k : {3, 17, 0, 12, 11, 19, 1}) {
    const BackgroundFrame& f = bg->frameAt((k + 0.5) / fps, d);
    EXPECT_EQ(f.index, k);
    EXPECT_EQ(decodedNumber(f), k) << "seek to " << k;
  }
  EXPECT_EQ(decodedNumber(bg->frameAt(20.0 / fps + 4.5 / fps, d)), 4);  // loops
  EXPECT_TRUE(d.ok()) << d.format();
}

TEST(BackgroundSource, ErrorsNameTheFile) {
  const fs::path dir = tempDir("errors");
  const std::string missingPhoto = (dir / "missing.png").string();
  Diagnostics d1;
  EXPECT_FALSE(openBackground(BackgroundKind::Still, missingPhoto, 0.0, d1));
  EXPECT_TRUE(mentions(d1, missingPhoto)) << d1.format();

  const std::string notAnImage = (dir / "fake.png").string();
  { std::ofstream(notAnImage) << "plain text"; }
  Diagnostics d2;
  EXPECT_FALSE(openBackground(BackgroundKind::Still, notAnImage, 0.0, d2));
  EXPECT_TRUE(mentions(d2, notAnImage)) << d2.format();

  const std::string missingVideo = (dir / "missing.avi").string();
  Diagnostics d3;
  EXPECT_FALSE(openBackground(BackgroundKind::Video, missingVideo, 0.0, d3));
  EXPECT_TRUE(mentions(d3, missingVideo)) << d3.format();

  const std::string badVideo = (dir / "bad.avi").string();
  { std::ofstream(badVideo) << "RIFF....AVI not really"; }
  Diagnostics d4;
  EXPECT_FALSE(openBackground(BackgroundKind::Video, badVideo, 0.0, d4));
  EXPECT_TRUE(mentions(d4, badVideo)) << d4.format();

  const std::string emptyPattern = (dir / "none_%03d.png").string();
  Diagnostics d5;
  EXPECT_FALSE(openBackground(BackgroundKind::Sequence, emptyPattern, 24.0, d5));
  EXPECT_TRUE(mentions(d5, emptyPattern)) << d5.format();

  Diagnostics d6;  // a sequence without a rate
  EXPECT_FALSE(openBackground(BackgroundKind::Sequence, dir.string(), 0.0, d6));
  EXPECT_TRUE(mentions(d6, dir.string())) << d6.format();

  // Frames of different sizes.
  const fs::path mixed = tempDir("mixed");
  writePng((mixed / "0.png").string(), framePixels(0));
  {
    const std::string small = (mixed / "1.png").string();
    auto out = OIIO::ImageOutput::create(small);
    ASSERT_TRUE(out->open(small, OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::UINT8)));
    std::vector<std::uint8_t> px(8 * 8 * 3, 0);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
  }
  Diagnostics d7;
  EXPECT_FALSE(openBackground(BackgroundKind::Sequence, (mixed / "%d.png").string(), 24.0, d7));
  EXPECT_TRUE(mentions(d7, (mixed / "1.png").string())) << d7.format();

  // A stray image of another size in a frames folder (the target's photo) is the one named,
  // with its size and the frames', whether it sorts after the frames or before them.
  for (const char* frameName : {"frame_%04d.png", "view_%04d.png"}) {
    SCOPED_TRACE(frameName);
    const fs::path folder = tempDir("stray");
    for (int k = 0; k < 3; ++k) {
      char name[32];
      std::snprintf(name, sizeof name, frameName, k);
      writePng((folder / name).string(), framePixels(k));
    }
    const std::string stray = (folder / "target.png").string();
    auto out = OIIO::ImageOutput::create(stray);
    ASSERT_TRUE(out->open(stray, OIIO::ImageSpec(8, 6, 3, OIIO::TypeDesc::UINT8)));
    std::vector<std::uint8_t> px(8 * 6 * 3, 0);
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    Diagnostics d8;
    EXPECT_FALSE(openBackground(BackgroundKind::Sequence, folder.string(), 24.0, d8));
    EXPECT_TRUE(mentions(d8, stray + ": error: image is 8x6 but the sequence's frames are 64x48 (3 of its 4 images"))
        << d8.format();
  }

  EXPECT_EQ(backgroundKindFromName("Video"), BackgroundKind::Video);
  EXPECT_EQ(backgroundKindFromName("still"), BackgroundKind::Still);
  EXPECT_FALSE(backgroundKindFromName("webcam"));
}
