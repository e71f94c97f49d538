// libFuzzer target: the markerless tracker's planar maps on disk (`--map`,
// marionette_ar/tracking/planar_map.hpp), read by parsePlanarMap from the bytes. The reader
// checks the trailing CRC-32 before any field, so almost every mutation would stop there:
// each input is parsed twice, as it is and with its last 4 bytes replaced by the CRC-32 of
// the rest, which takes the mutations on to the counts and field checks. Contract: no crash,
// no allocation past what the bytes hold; a refused map has an error and every diagnostic
// names the input; a map that reads is inside the documented limits (a camera without a
// problem(), 1..64 keyframes of 16..4096 a side, points in their image), writePlanarMap
// writes it back byte for byte, and readPlanarMap reads that file to the same map. With
// MARIONETTE_FUZZ_WRITE_SEED=folder the program writes two small valid maps there with
// writePlanarMap and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <cmath>
#include <cstring>
#include <iterator>

#include "fuzz_support.hpp"
#include "marionette_ar/tracking/planar_map.hpp"
#include "tracking_seeds.hpp"

using namespace marionette;
using fuzz::require;

namespace {

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool insideImage(float x, float y, const ar::PlanarKeyframe& k) {
  return x >= 0 && y >= 0 && x < static_cast<float>(k.width) && y < static_cast<float>(k.height);
}

bool sameFeature(const ar::PlanarFeature& a, const ar::PlanarFeature& b) {
  return a.x == b.x && a.y == b.y && a.size == b.size && a.angle == b.angle && a.response == b.response &&
         a.octave == b.octave && a.descriptor == b.descriptor;
}

bool sameMap(const ar::PlanarMap& a, const ar::PlanarMap& b) {
  const ar::CameraModel &c = a.camera, &d = b.camera;
  if (c.width != d.width || c.height != d.height || c.fx != d.fx || c.fy != d.fy || c.cx != d.cx || c.cy != d.cy ||
      c.distortion != d.distortion || a.targetWidth != b.targetWidth || a.targetHeight != b.targetHeight ||
      a.keyframes.size() != b.keyframes.size())
    return false;
  for (std::size_t i = 0; i < a.keyframes.size(); ++i) {
    const ar::PlanarKeyframe &k = a.keyframes[i], &l = b.keyframes[i];
    if (k.width != l.width || k.height != l.height || k.grey != l.grey || k.planeToImage != l.planeToImage ||
        k.corners != l.corners || k.features.size() != l.features.size())
      return false;
    for (std::size_t j = 0; j < k.features.size(); ++j)
      if (!sameFeature(k.features[j], l.features[j])) return false;
  }
  return true;
}

void check(const std::uint8_t* data, std::size_t size, const std::string& name) {
  Diagnostics d;
  const std::optional<ar::PlanarMap> map = ar::parsePlanarMap(data, size, name, d);
  if (!map) {
    fuzz::requireNamedFailure(d, name);
    return;
  }
  require(fuzz::allName(d, name), "a diagnostic does not name the input");
  require(map->camera.problem().empty(), "a map's camera has a problem()");
  require(std::isfinite(map->targetWidth) && std::isfinite(map->targetHeight) && map->targetWidth > 0 &&
              map->targetHeight > 0,
          "target size not a positive finite number");
  require(!map->keyframes.empty() && map->keyframes.size() <= ar::PlanarMap::kMaxKeyframes, "keyframe count");
  for (const ar::PlanarKeyframe& k : map->keyframes) {
    require(k.width >= 16 && k.height >= 16 && k.width <= ar::PlanarMap::kMaxKeyframeSide &&
                k.height <= ar::PlanarMap::kMaxKeyframeSide,
            "keyframe size outside 16..4096");
    require(k.grey.size() == static_cast<std::size_t>(k.width) * static_cast<std::size_t>(k.height),
            "grey image is not width x height");
    for (double v : k.planeToImage) require(std::isfinite(v), "plane-to-image not finite");
    require(k.corners.size() <= ar::PlanarMap::kMaxPointsPerKeyframe &&
                k.features.size() <= ar::PlanarMap::kMaxPointsPerKeyframe,
            "more points than the limit");
    for (const auto& c : k.corners) require(insideImage(c[0], c[1], k), "a corner outside its image");
    for (const ar::PlanarFeature& f : k.features)
      require(insideImage(f.x, f.y, k) && std::isfinite(f.size) && std::isfinite(f.angle) &&
                  std::isfinite(f.response) && f.octave >= 0 && f.octave <= 31,
              "a feature outside its image or without a valid scale");
  }
  // Every field that reads is exact (no NaN, no clamped count), so the writer gives the input back.
  const std::string copy = (fuzz::tempDir() / "copy.map").string();
  Diagnostics error;
  require(ar::writePlanarMap(copy, *map, error), "writePlanarMap failed on what parsePlanarMap read");
  const std::vector<std::uint8_t> written = readBytes(copy);
  require(written.size() == size && std::memcmp(written.data(), data, size) == 0,
          "writePlanarMap does not write the bytes it read");
  Diagnostics back;
  const std::optional<ar::PlanarMap> again = ar::readPlanarMap(copy, back);
  require(again.has_value() && back.ok(), "writePlanarMap's output does not read");
  require(sameMap(*map, *again), "the map does not round-trip");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    bool ok = true;
    for (int keyframes : {1, 2}) {  // each seed must read back, or the corpus starts from nothing
      const std::string path = std::string(dir) + "/keyframes" + std::to_string(keyframes) + ".map";
      Diagnostics error;
      Diagnostics d;
      if (!ar::writePlanarMap(path, fuzz::seedPlanarMap(keyframes), error) || !ar::readPlanarMap(path, d)) {
        std::fprintf(stderr, "cannot write the seed %s: %s%s\n", path.c_str(), error.format().c_str(), d.format().c_str());
        ok = false;
      }
    }
    std::exit(ok ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check(data, size, "in.map");
  if (size >= 4) {  // the same bytes with a checksum that matches them
    std::vector<std::uint8_t> patched(data, data + size);
    fuzz::patchMapChecksum(patched.data(), size);
    check(patched.data(), size, "in-crc.map");
  }
  return 0;
}
