#include "marionette/prt/transfer_cache.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "prt_code_hash.hpp"  // generated: a hash of this library's sources

namespace marionette::prt {

namespace {
constexpr char kMagic[8] = {'M', 'N', 'P', 'R', 'T', '\0', '\0', '\1'};
constexpr std::uint64_t kFormatVersion = 1;  // bump when the file layout changes
// Any change to the PRT code changes the key: a transfer another build computed is not read.
constexpr std::uint64_t kCodeHash = MARIONETTE_PRT_CODE_HASH;

struct Fnv1a {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void bytes(const void* data, std::size_t n) noexcept {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  }
  template <class T>
  void value(const T& v) noexcept { bytes(&v, sizeof v); }
};

struct Header {
  char magic[8];
  std::uint64_t key;
  std::uint32_t bands, shadowed;
  std::uint64_t vertices, rays;
};
}  // namespace

std::uint64_t transferCacheKey(const TransferMesh& mesh, const TransferOptions& s) noexcept {
  Fnv1a f;
  f.value(kFormatVersion);
  f.value(kCodeHash);
  f.value(mesh.positions.size());
  f.bytes(mesh.positions.data(), mesh.positions.size() * sizeof(glm::vec3));
  f.bytes(mesh.normals.data(), mesh.normals.size() * sizeof(glm::vec3));
  f.value(mesh.indices.size());
  f.bytes(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  f.value(s.bands);
  f.value(s.shadowed);
  if (s.shadowed) {  // the unshadowed transfer does not depend on these
    f.value(stratifiedRayCount(s.raysPerVertex));
    f.value(s.originOffset);
    f.value(s.seed);
  }
  return f.h;
}

std::string defaultTransferCacheDirectory() {
  if (const char* d = std::getenv("MARIONETTE_PRT_CACHE"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::string(d) + "/marionette/prt";
  if (const char* d = std::getenv("HOME"); d && *d) return std::string(d) + "/.cache/marionette/prt";
  return ".marionette-prt-cache";
}

std::string transferCachePath(const std::string& directory, std::uint64_t key) {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.mprt", static_cast<unsigned long long>(key));
  return (std::filesystem::path(directory) / name).string();
}

bool saveTransfer(const std::string& path, std::uint64_t key, const TransferOptions& settings,
                  const VertexTransfer& transfer, Diagnostics& diagnostics) {
  std::error_code ec;
  const std::filesystem::path target(path);
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path(), ec);
  const std::string temporary = path + ".tmp" + std::to_string(getpid());  // two writers never share it
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    Header h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.key = key;
    h.bands = static_cast<std::uint32_t>(transfer.bands);
    h.shadowed = settings.shadowed ? 1u : 0u;
    h.vertices = transfer.vertexCount();
    h.rays = settings.shadowed ? static_cast<std::uint64_t>(stratifiedRayCount(settings.raysPerVertex)) : 0u;
    out.write(reinterpret_cast<const char*>(&h), sizeof h);
    out.write(reinterpret_cast<const char*>(transfer.coefficients.data()),
              static_cast<std::streamsize>(transfer.coefficients.size() * sizeof(float)));
    out.write(reinterpret_cast<const char*>(transfer.occluded.data()),
              static_cast<std::streamsize>(transfer.occluded.size() * sizeof(float)));
    if (!out) {
      diagnostics.warning(path, "cannot write the PRT cache file (the transfer is not cached)");
      std::filesystem::remove(temporary, ec);
      return false;
    }
  }
  std::filesystem::rename(temporary, target, ec);
  if (ec) {
    diagnostics.warning(path, "cannot write the PRT cache file: " + ec.message());
    std::filesystem::remove(temporary, ec);
    return false;
  }
  return true;
}

std::optional<VertexTransfer> loadTransfer(const std::string& path, std::uint64_t key, std::size_t vertices, int bands,
                                           Diagnostics& diagnostics) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  Header h{};
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  const std::size_t count = static_cast<std::size_t>(bands) * static_cast<std::size_t>(bands);
  const auto size = std::filesystem::file_size(path, ec);
  const std::uintmax_t expected = sizeof h + (vertices * count + vertices) * sizeof(float);
  if (!in || std::memcmp(h.magic, kMagic, sizeof kMagic) != 0 || h.key != key || h.vertices != vertices ||
      h.bands != static_cast<std::uint32_t>(bands) || ec || size != expected) {
    diagnostics.warning(path, "PRT cache file does not match the mesh and settings (or is damaged); computing again");
    return std::nullopt;
  }
  VertexTransfer t;
  t.bands = bands;
  t.coefficients.resize(vertices * count);
  t.occluded.resize(vertices);
  in.read(reinterpret_cast<char*>(t.coefficients.data()), static_cast<std::streamsize>(t.coefficients.size() * sizeof(float)));
  in.read(reinterpret_cast<char*>(t.occluded.data()), static_cast<std::streamsize>(t.occluded.size() * sizeof(float)));
  if (!in) {
    diagnostics.warning(path, "PRT cache file is truncated; computing again");
    return std::nullopt;
  }
  const bool finite = std::all_of(t.coefficients.begin(), t.coefficients.end(), [](float v) { return std::isfinite(v); });
  const bool fractions = std::all_of(t.occluded.begin(), t.occluded.end(), [](float v) { return v >= 0.0f && v <= 1.0f; });
  if (!finite || !fractions) {
    diagnostics.warning(path, "PRT cache file holds non-finite values or occlusion outside 0..1; computing again");
    return std::nullopt;
  }
  return t;
}

CachedTransfer cachedTransfer(const TransferMesh& mesh, const TransferOptions& settings, const std::string& directory,
                              Diagnostics& diagnostics, const TransferProgress& progress) {
  CachedTransfer result;
  const std::uint64_t key = transferCacheKey(mesh, settings);
  result.path = transferCachePath(directory.empty() ? defaultTransferCacheDirectory() : directory, key);
  if (auto cached = loadTransfer(result.path, key, mesh.positions.size(), settings.bands, diagnostics)) {
    result.transfer = std::move(*cached);
    result.fromCache = true;
    return result;
  }
  std::unique_ptr<OcclusionTracer> tracer;
  if (settings.shadowed) {
    tracer = makeEmbreeOcclusion(mesh, diagnostics);
    if (!tracer) return result;
  }
  result.transfer = computeTransfer(mesh, settings, tracer.get(), diagnostics, progress, &result.stats);
  if (result.transfer.bands > 0) (void)saveTransfer(result.path, key, settings, result.transfer, diagnostics);
  return result;
}

}  // namespace marionette::prt
