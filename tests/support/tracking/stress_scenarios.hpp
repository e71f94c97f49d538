// Stress sequences for the trackers (issue 40, item 5): random hand-held camera paths from a
// seed, apart from the standard scenarios (scenarios.hpp, whose paths are orbits), in four
// classes:
//
//   pan          hand-held pans and turns about random axes (yaw, pitch, roll about the optical
//                axis, oblique) at up to 180 deg/s; the first takes the target out of view and
//                brings it back
//   reentry      the camera turns away until the target is out of view, comes back until only
//                15..45 % of it shows at a given image edge, hesitates there, then centres it
//   hands        one or two hands with their forearms, 5..25 cm above the floor, reaching in
//                over the target and away while the camera moves moderately
//   photometric  auto-exposure steps of 0.5..1.5 EV, white-balance steps, a defocus blur of up
//                to 4 px coming and going, with moderate motion
//
// Every frame is an exposure of 1/60..1/30 s (the seed picks it per sequence) rendered as the
// average of sub-frames spread over it (SequenceRenderer::renderExposure): the motion blur a
// moving camera makes, longer where the image moves faster (a roll smears the edges more than
// the centre), and hands moving during the exposure are smeared too. The sub-frame count
// follows the fastest image motion during the exposure. Noise (sigma 1..3) after averaging.
//
// Motion: a camera 2..3 target widths from the target, 40..65 deg above the floor, looking near
// its centre; slow drift of the eye, the aim and the roll, a hand's tremor (6..11 Hz, a few
// hundredths of a degree), and turns: each a rotation about a camera axis whose angle follows a
// quintic smoothstep (continuous acceleration), its duration long enough that neither the peak
// speed (180 deg/s in all, drift and tremor included) nor the angular acceleration (1500 deg/s^2
// for pans, 400 for the moderate classes) is exceeded. A turn pivots about a wrist 10..30 cm
// behind the camera, so that the camera also moves. Times: frame i is the exposure centred on
// i / 30 s; its pose (the truth a tracker should report) is the camera's at that instant. The
// path and the plans of the turns are hand_held_path.hpp's; the hands, the photometric effects
// and the frames are made here.
//
// Determinism: one SplitMix64 stream per (class, seed, purpose) and distributions written here
// (uniform from the top 53 bits), so that the same seed gives the same poses and, with the same
// libm and OpenCV, the same frames bit for bit, whatever the standard library.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/mat4x4.hpp>
#include <opencv2/core.hpp>

#include "tracking/scenario_run.hpp"
#include "tracking/scenarios.hpp"
#include "tracking/synthetic_sequence.hpp"

namespace marionette::ar::synthetic {

enum class StressClass : std::uint8_t { Pan, Reentry, Hands, Photometric };
inline constexpr std::array<StressClass, 4> kStressClasses{StressClass::Pan, StressClass::Reentry, StressClass::Hands,
                                                           StressClass::Photometric};
[[nodiscard]] std::string_view stressClassName(StressClass kind) noexcept;  // "pan", "reentry", ...
[[nodiscard]] std::optional<StressClass> stressClassNamed(std::string_view name) noexcept;

// The image edge through which the target comes back in a `reentry` sequence.
enum class ImageEdge : std::uint8_t { Left, Right, Top, Bottom };
[[nodiscard]] std::string_view imageEdgeName(ImageEdge edge) noexcept;

struct StressOptions {
  double pxPerSubFrame = 2.0;  // one sub-frame per this much of the fastest image motion
  int minSubFrames = 4;        // one of each of the 2x2 sample positions: antialiased when still
  int maxSubFrames = 16;        // the time it takes: 12 ms a sub-frame (a quarter of a render)
};

// One frame's exposure and what is known about it.
struct StressFrame {
  double time = 0;      // the exposure's middle, seconds
  double exposure = 0;  // seconds
  std::vector<SubFrame> subFrames;  // evenly spaced instants of the exposure, first to last
  double imageMotionPx = 0;  // the fastest image motion during the exposure (5 x 5 grid, hands)
  double blurPx = 0;         // path length of the target centre's image over the exposure; NaN
                             // when the centre is behind the camera
  double angularSpeedDeg = 0;  // the camera's, deg/s, at the middle
  double handsCover = 0;       // share of the target hidden by hands at the middle
                               // (SequenceRenderer::occludedTargetFraction)
};

struct StressSequence {
  StressClass kind = StressClass::Pan;
  std::uint64_t seed = 0;
  ImageEdge edge = ImageEdge::Left;  // reentry only
  double exposure = 0;               // seconds, the same for every frame
  // name "CLASS/SEED", fps 30, the true poses at the exposures' middles, the effects (gain,
  // channel gains, defocus, noise; no line motion blur: the sub-frames make it) and
  // renderer.visibleTargetFraction of each true pose.
  Scenario scenario;
  std::vector<StressFrame> frames;
  std::function<glm::dmat4(double)> cameraAt;  // the continuous path (camera-to-world at t s)
};

// The generators. frames >= 30 (std::invalid_argument otherwise); the moves are fitted into the
// sequence's length, so fewer frames have faster moves. The renderer gives the camera and the
// target (distances scale with its width; hands are life-size).
[[nodiscard]] StressSequence panSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                         const StressOptions& options = {});
// The edge is the seed's: left for seeds 1..4, right 5..8, top 9..12, bottom 13..16, then
// again, so that both of the harness's plans (stress_run.hpp: seeds 1..N of every class, or
// seed s of class (s - 1) % 4) see every edge.
[[nodiscard]] StressSequence reentrySequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                             const StressOptions& options = {});
[[nodiscard]] StressSequence reentrySequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                             ImageEdge edge, const StressOptions& options = {});
[[nodiscard]] StressSequence handsSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                           const StressOptions& options = {});
[[nodiscard]] StressSequence photometricSequence(const SequenceRenderer& renderer, std::uint64_t seed, int frames,
                                                 const StressOptions& options = {});
[[nodiscard]] StressSequence stressSequence(const SequenceRenderer& renderer, StressClass kind, std::uint64_t seed,
                                            int frames, const StressOptions& options = {});
// The harness's lengths, a minute for 20 sequences with the tracker (docs/tracking.md): 50
// frames for pan, 60 (2 s) for reentry, whose three turns need the time, 40 for the others.
[[nodiscard]] int defaultStressFrames(StressClass kind) noexcept;

// Frame i of the sequence (renderer.renderExposure of its sub-frames with its effects).
void renderStressFrame(const SequenceRenderer& renderer, const StressSequence& sequence, int frame, cv::Mat& outRgb);

// Every frame, `threads` frames at a time (each frame's own rendering on one thread: call
// cv::setNumThreads(1) first for the fastest). The frames' render times (ms, each on its thread)
// go to msPerFrame when given. The bits do not depend on the thread count.
[[nodiscard]] RenderedScenario renderStress(const SequenceRenderer& renderer, const StressSequence& sequence,
                                            int threads = 2, std::vector<double>* msPerFrame = nullptr);

// A hand and its forearm, RGBA8 (straight alpha), `texel` metres a texel: the hand with the
// fingers along +u, the thumb on +v, the palm's centre at palmTexel and the wrist at wristTexel;
// the forearm from the wrist (column 0) along +u. A skin tone, shading, mottling, knuckle creases
// and nails from the seed.
struct HandPicture {
  cv::Mat hand, forearm;
  cv::Point2d palmTexel, wristTexel;
  double texel = 0.001;
};
[[nodiscard]] HandPicture handPicture(std::uint64_t seed);

}  // namespace marionette::ar::synthetic
