// libFuzzer target: recorded pose CSVs (marionette_ar/pose_track.hpp: what `marionette-ar track`
// writes and a replayed camera reads), parsed from memory by parsePoseTrack. Contract: no crash;
// a refused text has an error and every diagnostic names the file; a track that parses has
// rows with strictly increasing frames and times, finite poses whose rotations are
// orthonormal, and atFrame finds each row. With MARIONETTE_FUZZ_WRITE_SEED=folder the program
// writes its seed there and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <cmath>

#include <glm/mat3x3.hpp>

#include "fuzz_support.hpp"
#include "marionette_ar/pose_track.hpp"
#include "pose_track_seed.hpp"

using namespace marionette;
using fuzz::require;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    std::ofstream(std::string(dir) + "/poses.csv", std::ios::binary) << fuzz::kSeedPoseTrack;
    std::ofstream(std::string(dir) + "/poses_sigmas.csv", std::ios::binary) << fuzz::kSeedPoseTrackWithSigmas;
    Diagnostics d;
    std::exit(ar::parsePoseTrack(fuzz::kSeedPoseTrack, "seed", d) &&
                      ar::parsePoseTrack(fuzz::kSeedPoseTrackWithSigmas, "seed", d)
                  ? 0
                  : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Diagnostics d;
  const std::optional<ar::PoseTrack> track = ar::parsePoseTrack(text, "in.csv", d);
  if (!track) {
    fuzz::requireNamedFailure(d, "in.csv");
    return 0;
  }
  require(fuzz::allName(d, "in.csv"), "a diagnostic does not name the file");
  require(!track->rows().empty(), "a track without rows");
  for (std::size_t r = 0; r < track->rows().size(); ++r) {
    const ar::RecordedPose& row = track->rows()[r];
    require(std::isfinite(row.time) && row.time >= 0, "a time that is not finite and >= 0");
    if (r > 0) require(row.frame > track->rows()[r - 1].frame && row.time > track->rows()[r - 1].time, "rows out of order");
    for (int c = 0; c < 4; ++c)
      for (int k = 0; k < 4; ++k) require(std::isfinite(row.cameraToWorld[c][k]), "a pose that is not finite");
    require(std::abs(glm::determinant(glm::dmat3(row.cameraToWorld)) - 1.0) < 1e-9, "a rotation that is not one");
    require(track->atFrame(row.frame) == &row, "atFrame does not find a row");
  }
  return 0;
}
