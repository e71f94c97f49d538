#include "marionette_ar/background_source.hpp"

#include <OpenImageIO/imageio.h>

#include "marionette/core/limits.hpp"
#include "marionette/core/enum_names.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <regex>
#include <utility>

namespace marionette::ar {

namespace fs = std::filesystem;

std::int64_t BackgroundSource::frameIndexAt(double seconds) const noexcept {
  const std::int64_t count = frameCount();
  const double rate = fps();
  if (count <= 1 || !(rate > 0.0) || !(seconds > 0.0)) return 0;
  // The small epsilon keeps t = k / fps (computed in floating point) on frame k.
  const double k = std::floor(seconds * rate + 1e-6);
  if (k >= static_cast<double>(count)) {
    if (playback_ == Playback::Hold) return count - 1;
    return static_cast<std::int64_t>(std::fmod(k, static_cast<double>(count)));
  }
  return static_cast<std::int64_t>(k);
}

std::optional<BackgroundKind> backgroundKindFromName(const std::string& name) {
  static constexpr EnumName<BackgroundKind> kNames[] = {
      {"still", BackgroundKind::Still},       {"image", BackgroundKind::Still},
      {"photo", BackgroundKind::Still},       {"sequence", BackgroundKind::Sequence},
      {"image_sequence", BackgroundKind::Sequence}, {"video", BackgroundKind::Video}};
  return valueOfName<BackgroundKind>(name, kNames, NameCase::Ignored);
}

bool readImageRgb8(const std::string& path, BackgroundFrame& frame, Diagnostics& diagnostics) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    diagnostics.error(path, fs::exists(path, ec) ? "background image is not a regular file" : "background image not found");
    return false;
  }
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    diagnostics.error(path, "cannot read the background image: " + OIIO::geterror());
    return false;
  }
  const OIIO::ImageSpec& spec = input->spec();
  const int w = spec.width, h = spec.height, nch = spec.nchannels;
  if (w <= 0 || h <= 0 || nch <= 0) {
    diagnostics.error(path, "background image has no pixels");
    return false;
  }
  if (const std::string problem = limits::imageSizeProblem(w, h, nch); !problem.empty()) {
    diagnostics.error(path, "background image " + problem);
    return false;
  }
  std::vector<std::uint8_t> all(static_cast<std::size_t>(w) * h * nch);
  if (!input->read_image(0, 0, 0, nch, OIIO::TypeDesc::UINT8, all.data())) {
    diagnostics.error(path, "cannot decode the background image: " + input->geterror());
    return false;
  }
  frame.width = w, frame.height = h;
  frame.rgb.resize(static_cast<std::size_t>(w) * h * 3);
  const std::size_t count = static_cast<std::size_t>(w) * h;
  for (std::size_t i = 0; i < count; ++i)
    for (int c = 0; c < 3; ++c) frame.rgb[i * 3 + c] = all[i * nch + (nch >= 3 ? c : 0)];
  return true;
}

namespace {

// Width and height from the file's header only (no pixel decoding).
bool imageSize(const std::string& path, int& w, int& h, Diagnostics& diagnostics) {
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    diagnostics.error(path, "cannot read the image: " + OIIO::geterror());
    return false;
  }
  w = input->spec().width, h = input->spec().height;
  return true;
}

class StillSource final : public BackgroundSource {
 public:
  explicit StillSource(BackgroundFrame frame) : frame_(std::move(frame)) { frame_.index = 0; }
  const BackgroundFrame& frameAt(double, Diagnostics&) override { return frame_; }
  int width() const noexcept override { return frame_.width; }
  int height() const noexcept override { return frame_.height; }
  double fps() const noexcept override { return 0.0; }
  std::int64_t frameCount() const noexcept override { return 1; }
  std::int64_t decodedFrames() const noexcept override { return 1; }

 private:
  BackgroundFrame frame_;
};

class SequenceSource final : public BackgroundSource {
 public:
  SequenceSource(std::vector<std::string> files, double rate, Playback playback)
      : files_(std::move(files)), fps_(rate) {
    playback_ = playback;
  }
  bool open(Diagnostics& diagnostics) {
    // The sequence's size is the one most of its images have (the first file's on a tie): a
    // stray image in a frames folder (the target's photo) is the one named, wherever it sorts.
    std::vector<std::pair<int, int>> sizes(files_.size());
    std::map<std::pair<int, int>, std::size_t> counts;
    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (!imageSize(files_[i], sizes[i].first, sizes[i].second, diagnostics)) return false;
      ++counts[sizes[i]];
    }
    std::size_t common = 0;
    for (std::size_t i = 1; i < files_.size(); ++i)
      if (counts[sizes[i]] > counts[sizes[common]]) common = i;
    width_ = sizes[common].first, height_ = sizes[common].second;
    for (std::size_t i = 0; i < files_.size(); ++i) {
      if (sizes[i] == sizes[common]) continue;
      const std::string size = std::to_string(sizes[i].first) + "x" + std::to_string(sizes[i].second);
      diagnostics.error(files_[i], "image is " + size + " but the sequence's frames are " + std::to_string(width_) + "x" +
                                       std::to_string(height_) + " (" + std::to_string(counts[sizes[common]]) +
                                       " of its " + std::to_string(files_.size()) + " images, " + files_[common] +
                                       " the first): not a frame of this sequence?");
      return false;
    }
    return decode(0, diagnostics);
  }
  const BackgroundFrame& frameAt(double seconds, Diagnostics& diagnostics) override {
    const std::int64_t k = frameIndexAt(seconds);
    if (k != frame_.index) decode(k, diagnostics);
    return frame_;
  }
  int width() const noexcept override { return width_; }
  int height() const noexcept override { return height_; }
  double fps() const noexcept override { return fps_; }
  std::int64_t frameCount() const noexcept override { return static_cast<std::int64_t>(files_.size()); }
  std::int64_t decodedFrames() const noexcept override { return decoded_; }

 private:
  bool decode(std::int64_t k, Diagnostics& diagnostics) {
    BackgroundFrame next;
    const std::string& file = files_[static_cast<std::size_t>(k)];
    if (!readImageRgb8(file, next, diagnostics)) return false;
    ++decoded_;
    if (next.width != width_ || next.height != height_) {
      diagnostics.error(file, "sequence frame changed size since the sequence was opened");
      return false;
    }
    next.index = k;
    frame_ = std::move(next);
    return true;
  }
  std::vector<std::string> files_;
  double fps_ = 0.0;
  int width_ = 0, height_ = 0;
  std::int64_t decoded_ = 0;
  BackgroundFrame frame_;
};

class VideoSource final : public BackgroundSource {
 public:
  VideoSource(std::string path, Playback playback) : path_(std::move(path)) { playback_ = playback; }
  bool open(Diagnostics& diagnostics) {
    std::error_code ec;
    if (!fs::is_regular_file(path_, ec)) {
      diagnostics.error(path_, fs::exists(path_, ec) ? "background video is not a regular file" : "background video not found");
      return false;
    }
    // FFmpeg backend only: the others (GStreamer, image-sequence, camera backends) would
    // probe devices and log noise for a file FFmpeg rejects, and add nothing for files.
    if (!capture_.open(path_, cv::CAP_FFMPEG) || !capture_.isOpened()) {
      diagnostics.error(path_, "OpenCV (FFmpeg) cannot open the background video (unknown container or codec)");
      return false;
    }
    fps_ = capture_.get(cv::CAP_PROP_FPS);
    if (!(fps_ > 0.0) || !std::isfinite(fps_)) {
      diagnostics.error(path_, "background video has no frame rate");
      return false;
    }
    width_ = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_WIDTH));
    height_ = static_cast<int>(capture_.get(cv::CAP_PROP_FRAME_HEIGHT));
    count_ = static_cast<std::int64_t>(capture_.get(cv::CAP_PROP_FRAME_COUNT));
    if (count_ <= 0) {  // the container does not say: count by demuxing once, then rewind
      count_ = 0;
      while (capture_.grab()) ++count_;
      capture_.set(cv::CAP_PROP_POS_FRAMES, 0.0);
      next_ = 0;
    }
    if (count_ <= 0) {
      diagnostics.error(path_, "background video has no frames");
      return false;
    }
    return decode(0, diagnostics);
  }
  const BackgroundFrame& frameAt(double seconds, Diagnostics& diagnostics) override {
    const std::int64_t k = frameIndexAt(seconds);
    if (k != frame_.index) decode(k, diagnostics);
    return frame_;
  }
  int width() const noexcept override { return width_; }
  int height() const noexcept override { return height_; }
  double fps() const noexcept override { return fps_; }
  std::int64_t frameCount() const noexcept override { return count_; }
  std::int64_t decodedFrames() const noexcept override { return decoded_; }

 private:
  // Forward by up to this many frames: decode through them; further, or backwards: seek.
  static constexpr std::int64_t kMaxSkip = 48;

  bool decode(std::int64_t k, Diagnostics& diagnostics) {
    if (k < next_ || k - next_ > kMaxSkip) {
      if (!capture_.set(cv::CAP_PROP_POS_FRAMES, static_cast<double>(k))) {
        diagnostics.error(path_, "cannot seek the background video to frame " + std::to_string(k));
        return false;
      }
      next_ = k;
    }
    for (; next_ < k; ++next_, ++decoded_) {
      if (!capture_.grab()) return fail(k, diagnostics);
    }
    cv::Mat bgr;
    if (!capture_.read(bgr) || bgr.empty()) return fail(k, diagnostics);
    ++decoded_;
    ++next_;
    cv::Mat rgb;
    if (bgr.channels() == 1) {
      cv::cvtColor(bgr, rgb, cv::COLOR_GRAY2RGB);
    } else if (bgr.channels() == 4) {
      cv::cvtColor(bgr, rgb, cv::COLOR_BGRA2RGB);
    } else {
      cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    }
    if (rgb.depth() != CV_8U) rgb.convertTo(rgb, CV_8U);
    frame_.width = rgb.cols, frame_.height = rgb.rows;
    frame_.rgb.resize(static_cast<std::size_t>(rgb.cols) * rgb.rows * 3);
    for (int r = 0; r < rgb.rows; ++r)
      std::copy_n(rgb.ptr<std::uint8_t>(r), static_cast<std::size_t>(rgb.cols) * 3,
                  frame_.rgb.data() + static_cast<std::size_t>(r) * rgb.cols * 3);
    frame_.index = k;
    return true;
  }
  bool fail(std::int64_t k, Diagnostics& diagnostics) {
    diagnostics.error(path_, "cannot decode frame " + std::to_string(k) + " of the background video");
    next_ = std::numeric_limits<std::int64_t>::max();  // force a seek next time
    return false;
  }

  std::string path_;
  cv::VideoCapture capture_;
  double fps_ = 0.0;
  int width_ = 0, height_ = 0;
  std::int64_t count_ = 0;
  std::int64_t next_ = 0;  // the frame the next grab/read returns
  std::int64_t decoded_ = 0;
  BackgroundFrame frame_;
};

bool isImageExtension(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const char* const known[] = {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".tif", ".tiff",
                                      ".bmp", ".tga", ".webp", ".ppm", ".pgm", ".pnm", ".dpx"};
  return std::any_of(std::begin(known), std::end(known), [&](const char* k) { return e == k; });
}

// The files of a sequence: every image in a directory sorted by name, the numbered files
// matching a printf-style pattern (one %d or %0Nd in the file name), sorted by number, or one
// image file.
std::vector<std::string> sequenceFiles(const std::string& path, Diagnostics& diagnostics) {
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    for (const auto& entry : fs::directory_iterator(path, ec))
      if (entry.is_regular_file() && isImageExtension(entry.path())) files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    if (files.empty()) diagnostics.error(path, "image sequence directory holds no image files");
    return files;
  }
  // One file: a sequence of one frame (`track --images photo.png`); a file that is not an image
  // is named when its size is read.
  if (fs::is_regular_file(path, ec)) {
    files.push_back(path);
    return files;
  }
  const fs::path p(path);
  const std::string name = p.filename().string();
  static const std::regex spec(R"(%(0?)(\d*)d)");
  std::smatch m;
  if (!std::regex_search(name, m, spec)) {
    diagnostics.error(path, fs::exists(path, ec) ? "image sequence is neither a directory, an image file nor a "
                                                   "pattern with %d"
                                                 : "image sequence not found (neither a directory, an image file "
                                                   "nor a pattern with %d such as frames/%04d.png)");
    return files;
  }
  const std::string prefix = m.prefix().str(), suffix = m.suffix().str();
  if (suffix.find('%') != std::string::npos || prefix.find('%') != std::string::npos) {
    diagnostics.error(path, "image sequence pattern must hold exactly one %d");
    return files;
  }
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec)) {
    diagnostics.error(path, "image sequence folder " + dir.string() + " not found");
    return files;
  }
  const std::string printfFormat = "%" + m[1].str() + m[2].str() + "lld";
  std::vector<std::pair<long long, std::string>> numbered;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    const std::string f = entry.path().filename().string();
    if (f.size() <= prefix.size() + suffix.size() || f.compare(0, prefix.size(), prefix) != 0 ||
        f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = f.substr(prefix.size(), f.size() - prefix.size() - suffix.size());
    if (digits.empty() || digits.size() > 18 ||
        !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    const long long number = std::stoll(digits);
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, printfFormat.c_str(), number);
    if (digits != buffer) continue;  // e.g. "7" does not match %04d
    numbered.emplace_back(number, entry.path().string());
  }
  std::sort(numbered.begin(), numbered.end());
  for (auto& n : numbered) files.push_back(std::move(n.second));
  if (files.empty()) diagnostics.error(path, "no files match the image sequence pattern");
  return files;
}

}  // namespace

std::unique_ptr<BackgroundSource> openBackground(BackgroundKind kind, const std::string& path, double fps,
                                                 Diagnostics& diagnostics, Playback playback) {
  switch (kind) {
    case BackgroundKind::Still: {
      BackgroundFrame frame;
      if (!readImageRgb8(path, frame, diagnostics)) return nullptr;
      return std::make_unique<StillSource>(std::move(frame));
    }
    case BackgroundKind::Sequence: {
      if (!(fps > 0.0) || !std::isfinite(fps)) {
        diagnostics.error(path, "image sequence needs a frame rate > 0 (got " + std::to_string(fps) + ")");
        return nullptr;
      }
      std::vector<std::string> files = sequenceFiles(path, diagnostics);
      if (files.empty()) return nullptr;
      auto source = std::make_unique<SequenceSource>(std::move(files), fps, playback);
      if (!source->open(diagnostics)) return nullptr;
      return source;
    }
    case BackgroundKind::Video: {
      auto source = std::make_unique<VideoSource>(path, playback);
      if (!source->open(diagnostics)) return nullptr;
      return source;
    }
  }
  diagnostics.error(path, "unknown background kind");
  return nullptr;
}

}  // namespace marionette::ar
