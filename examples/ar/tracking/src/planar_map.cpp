#include "marionette_ar/tracking/planar_map.hpp"

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace marionette::ar {

namespace {

constexpr char kMagic[8] = {'M', 'N', 'P', 'L', 'A', 'N', 'A', 'R'};
constexpr std::size_t kFeatureBytes = 5 * 4 + 4 + 32;
constexpr std::uintmax_t kMaxMapBytes = 512ull << 20;

std::uint32_t crc(const std::uint8_t* data, std::size_t size) {
  uLong c = crc32(0L, Z_NULL, 0);
  while (size > 0) {  // zlib takes a uInt length
    const uInt chunk = static_cast<uInt>(std::min<std::size_t>(size, 1u << 30));
    c = crc32(c, data, chunk);
    data += chunk;
    size -= chunk;
  }
  return static_cast<std::uint32_t>(c);
}

class Writer {
 public:
  std::vector<std::uint8_t> bytes;
  template <class T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));  // x86-64 and AArch64 are little-endian
  }
  void raw(const std::uint8_t* p, std::size_t n) { bytes.insert(bytes.end(), p, p + n); }
};

// Reads with a bounds check on every field; `fail()` records where it stopped.
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  template <class T>
  bool get(T& v) {
    if (size_ - pos_ < sizeof(T)) return false;
    std::memcpy(&v, data_ + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  bool raw(std::uint8_t* p, std::size_t n) {
    if (size_ - pos_ < n) return false;
    std::memcpy(p, data_ + pos_, n);
    pos_ += n;
    return true;
  }
  [[nodiscard]] std::size_t left() const { return size_ - pos_; }
  [[nodiscard]] std::size_t pos() const { return pos_; }

 private:
  const std::uint8_t* data_;
  std::size_t size_, pos_ = 0;
};

}  // namespace

bool writePlanarMap(const std::string& file, const PlanarMap& map, Diagnostics& diagnostics) {
  Writer w;
  w.raw(reinterpret_cast<const std::uint8_t*>(kMagic), sizeof kMagic);
  w.put<std::uint32_t>(PlanarMap::kVersion);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(map.camera.width));
  w.put<std::uint32_t>(static_cast<std::uint32_t>(map.camera.height));
  for (double v : {map.camera.fx, map.camera.fy, map.camera.cx, map.camera.cy}) w.put(v);
  for (double v : map.camera.distortion) w.put(v);
  w.put(map.targetWidth);
  w.put(map.targetHeight);
  w.put<std::uint32_t>(static_cast<std::uint32_t>(map.keyframes.size()));
  for (const PlanarKeyframe& k : map.keyframes) {
    w.put<std::uint32_t>(static_cast<std::uint32_t>(k.width));
    w.put<std::uint32_t>(static_cast<std::uint32_t>(k.height));
    for (double v : k.planeToImage) w.put(v);
    w.raw(k.grey.data(), k.grey.size());
    w.put<std::uint32_t>(static_cast<std::uint32_t>(k.corners.size()));
    for (const auto& c : k.corners) {
      w.put(c[0]);
      w.put(c[1]);
    }
    w.put<std::uint32_t>(static_cast<std::uint32_t>(k.features.size()));
    for (const PlanarFeature& f : k.features) {
      for (float v : {f.x, f.y, f.size, f.angle, f.response}) w.put(v);
      w.put(f.octave);
      w.raw(f.descriptor.data(), f.descriptor.size());
    }
  }
  w.put<std::uint32_t>(crc(w.bytes.data(), w.bytes.size()));
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(w.bytes.data()), static_cast<std::streamsize>(w.bytes.size()));
  if (!out) {
    diagnostics.error(file, "the map cannot be written");
    return false;
  }
  return true;
}

std::optional<PlanarMap> parsePlanarMap(const std::uint8_t* data, std::size_t size, const std::string& name,
                                        Diagnostics& diagnostics) {
  auto fail = [&](const std::string& what) {
    diagnostics.error(name, what);
    return std::nullopt;
  };
  if (size < sizeof kMagic + 8 || std::memcmp(data, kMagic, sizeof kMagic) != 0)
    return fail("not a Marionette planar map (no MNPLANAR header)");
  std::uint32_t stored = 0;
  std::memcpy(&stored, data + size - 4, 4);
  Reader r(data + sizeof kMagic, size - sizeof kMagic - 4);
  std::uint32_t version = 0;
  (void)r.get(version);
  if (version != PlanarMap::kVersion)
    return fail("map version " + std::to_string(version) + "; this build reads version " +
                std::to_string(PlanarMap::kVersion));
  // The checksum first: a truncated or damaged map is reported as such, not as whatever
  // field the damage happens to hit.
  if (crc(data, size - 4) != stored) return fail("checksum mismatch: the map is truncated or corrupted");

  auto truncated = [&](const char* where) {
    return fail(std::string("truncated in ") + where + " at byte " + std::to_string(sizeof kMagic + r.pos()));
  };
  PlanarMap map;
  map.checksum = stored;
  std::uint32_t w = 0, h = 0, count = 0;
  if (!r.get(w) || !r.get(h)) return truncated("the camera size");
  map.camera.width = static_cast<int>(std::min<std::uint32_t>(w, 1u << 30));
  map.camera.height = static_cast<int>(std::min<std::uint32_t>(h, 1u << 30));
  for (double* v : {&map.camera.fx, &map.camera.fy, &map.camera.cx, &map.camera.cy})
    if (!r.get(*v)) return truncated("the camera");
  for (double& v : map.camera.distortion)
    if (!r.get(v)) return truncated("the camera");
  if (const std::string p = map.camera.problem(); !p.empty()) return fail("the map's camera: " + p);
  if (!r.get(map.targetWidth) || !r.get(map.targetHeight)) return truncated("the target size");
  if (!std::isfinite(map.targetWidth) || !std::isfinite(map.targetHeight) || !(map.targetWidth > 0) ||
      !(map.targetHeight > 0) || map.targetWidth > 1e4 || map.targetHeight > 1e4)
    return fail("target size is not a positive number of metres up to 10 km");
  if (!r.get(count)) return truncated("the keyframe count");
  if (count < 1 || count > PlanarMap::kMaxKeyframes)
    return fail(std::to_string(count) + " keyframes: a map has 1 to " + std::to_string(PlanarMap::kMaxKeyframes));
  map.keyframes.resize(count);
  for (std::uint32_t i = 0; i < count; ++i) {
    PlanarKeyframe& k = map.keyframes[i];
    const std::string where = "keyframe " + std::to_string(i);
    if (!r.get(w) || !r.get(h)) return truncated(where.c_str());
    if (w < 16 || h < 16 || w > PlanarMap::kMaxKeyframeSide || h > PlanarMap::kMaxKeyframeSide)
      return fail(where + ": image " + std::to_string(w) + "x" + std::to_string(h) + " is outside 16..4096 a side");
    k.width = static_cast<int>(w);
    k.height = static_cast<int>(h);
    for (double& v : k.planeToImage)
      if (!r.get(v) || !std::isfinite(v)) return fail(where + ": plane-to-image homography is truncated or not finite");
    if (std::size_t(w) * h > r.left()) return truncated((where + " image").c_str());
    k.grey.resize(std::size_t(w) * h);
    (void)r.raw(k.grey.data(), k.grey.size());
    std::uint32_t n = 0;
    if (!r.get(n)) return truncated((where + " corners").c_str());
    if (n > PlanarMap::kMaxPointsPerKeyframe || std::size_t(n) * 8 > r.left())
      return fail(where + ": " + std::to_string(n) + " corners are more than the limit or the bytes left");
    k.corners.resize(n);
    for (auto& c : k.corners) {
      (void)r.get(c[0]);
      (void)r.get(c[1]);
      if (!(c[0] >= 0 && c[1] >= 0 && c[0] < static_cast<float>(w) && c[1] < static_cast<float>(h)))
        return fail(where + ": a corner lies outside its image");
    }
    if (!r.get(n)) return truncated((where + " features").c_str());
    if (n > PlanarMap::kMaxPointsPerKeyframe || std::size_t(n) * kFeatureBytes > r.left())
      return fail(where + ": " + std::to_string(n) + " features are more than the limit or the bytes left");
    k.features.resize(n);
    for (PlanarFeature& f : k.features) {
      for (float* v : {&f.x, &f.y, &f.size, &f.angle, &f.response}) (void)r.get(*v);
      (void)r.get(f.octave);
      (void)r.raw(f.descriptor.data(), f.descriptor.size());
      if (!(f.x >= 0 && f.y >= 0 && f.x < static_cast<float>(w) && f.y < static_cast<float>(h)) ||
          !std::isfinite(f.size) || !std::isfinite(f.angle) || !std::isfinite(f.response) || f.octave < 0 ||
          f.octave > 31)
        return fail(where + ": a feature lies outside its image or has no valid scale");
    }
  }
  if (r.left() != 0) return fail(std::to_string(r.left()) + " bytes after the last keyframe");
  return map;
}

std::optional<PlanarMap> readPlanarMap(const std::string& file, Diagnostics& diagnostics) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (ec) {
    diagnostics.error(file, "map file does not exist or cannot be read");
    return std::nullopt;
  }
  if (size > kMaxMapBytes) {
    diagnostics.error(file, "map file is larger than 512 MiB");
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!in) {
    diagnostics.error(file, "map file cannot be read");
    return std::nullopt;
  }
  return parsePlanarMap(bytes.data(), bytes.size(), file, diagnostics);
}

}  // namespace marionette::ar
