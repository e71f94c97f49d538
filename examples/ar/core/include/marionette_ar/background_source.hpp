// What the AR renderer draws behind the scene when there is no live camera: a still photo,
// an image sequence or a video file, as an RGB8 frame chosen by scene time.
//
// Frames: RGB8, 3 bytes per pixel, rows top to bottom, no row padding. To upload with
// glTexImage2D set GL_UNPACK_ALIGNMENT to 1 (rows are width*3 bytes) and either flip t or
// draw the quad with t = 1 at the top. Only 8 bits per channel: a 16-bit or float image is
// scaled or clamped to [0, 255] without any tone mapping or transfer function (the bytes are
// whatever the file's encoding is, normally sRGB).
//
// Timing: frame k of a sequence or video covers scene time [k / fps, (k + 1) / fps). Past
// the last frame the source loops (default) or holds the last frame (Playback::Hold).
// Negative times show frame 0. `index` is the source frame number (0-based) and changes
// exactly when the pixels change, so the renderer re-uploads when it differs from the last
// one it uploaded (a loop back to 0 changes it too).
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar {

struct BackgroundFrame {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  // width * height * 3 bytes, rows top to bottom
  std::int64_t index = -1;        // source frame number; -1 before the first decode
};

enum class Playback { Loop, Hold };

class BackgroundSource {
 public:
  virtual ~BackgroundSource() = default;

  // The frame for scene time `seconds`. The reference stays valid (and unchanged) until the
  // next call. If a frame cannot be decoded mid-playback, an error naming the file goes to
  // `diagnostics` and the previous frame stays (black if none was decoded).
  virtual const BackgroundFrame& frameAt(double seconds, Diagnostics& diagnostics) = 0;

  [[nodiscard]] virtual int width() const noexcept = 0;
  [[nodiscard]] virtual int height() const noexcept = 0;
  // Frames per second (0 for a still) and number of frames (1 for a still).
  [[nodiscard]] virtual double fps() const noexcept = 0;
  [[nodiscard]] virtual std::int64_t frameCount() const noexcept = 0;
  // How many frames were decoded since opening (tests: sequential playback decodes each
  // frame once; it never re-decodes from the start).
  [[nodiscard]] virtual std::int64_t decodedFrames() const noexcept = 0;

  // The source frame number shown at `seconds` (what frameAt(seconds).index will be).
  [[nodiscard]] std::int64_t frameIndexAt(double seconds) const noexcept;

 protected:
  Playback playback_ = Playback::Loop;
};

enum class BackgroundKind {
  Still,     // one image, any format OpenImageIO reads
  Sequence,  // a printf-style pattern ("frames/%04d.png": the files that exist, by number),
             // a directory (every image file in it, sorted by name) or one image file (one frame)
  Video,     // a video file OpenCV's VideoCapture opens with its FFmpeg backend (fps from the file)
};

// "still" / "image", "sequence", "video" (as a scene file names them); empty when unknown.
[[nodiscard]] std::optional<BackgroundKind> backgroundKindFromName(const std::string& name);

// Opens a background. `fps` is used by sequences only (must be > 0 for them); a video's rate
// comes from the file and a still has none. Errors (nullptr) name the file: missing,
// unreadable, a pattern or directory without images, frames of different sizes, a video
// OpenCV cannot open or decode. The first frame is decoded here, so an unreadable first
// frame is an error now rather than later.
[[nodiscard]] std::unique_ptr<BackgroundSource> openBackground(BackgroundKind kind, const std::string& path,
                                                               double fps, Diagnostics& diagnostics,
                                                               Playback playback = Playback::Loop);

// Reads one image file as RGB8 (grey copied to R, G, B; alpha and extra channels dropped).
// False with an error naming the file if it cannot.
[[nodiscard]] bool readImageRgb8(const std::string& path, BackgroundFrame& frame, Diagnostics& diagnostics);

}  // namespace marionette::ar
