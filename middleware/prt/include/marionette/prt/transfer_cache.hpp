// Transfer vectors cached on disk, so that a relaunch skips the precompute.
//
// The key hashes everything the result depends on: the mesh's positions, normals and
// triangles (bytes), the settings (bands, rays, shadowed, origin offset, seed), the
// format version and the code (a hash of marionette::prt's sources, made at build time), so
// a file cached by another build of the library is computed again. The file is <directory>/<key as 16 hex digits>.mprt:
//   "MNPRT\0\0\1" | u64 key | u32 bands | u32 shadowed | u64 vertices | u64 rays per vertex |
//   float coefficients[vertices * bands^2] | float occluded[vertices]      (little-endian)
// It is written to a temporary name and renamed, so a crash never leaves half a file. A file
// that does not match (other key, wrong size, truncated) is reported as a warning naming it,
// and the transfer is computed again.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "marionette/core/diagnostic.hpp"
#include "marionette/prt/transfer.hpp"

namespace marionette::prt {

[[nodiscard]] std::uint64_t transferCacheKey(const TransferMesh& mesh, const TransferOptions& settings) noexcept;
// $MARIONETTE_PRT_CACHE, else $XDG_CACHE_HOME/marionette/prt, else $HOME/.cache/marionette/prt,
// else ./.marionette-prt-cache.
[[nodiscard]] std::string defaultTransferCacheDirectory();
[[nodiscard]] std::string transferCachePath(const std::string& directory, std::uint64_t key);

bool saveTransfer(const std::string& path, std::uint64_t key, const TransferOptions& settings,
                  const VertexTransfer& transfer, Diagnostics& diagnostics);
// Empty when the file does not exist (silently) or does not match (with a warning).
[[nodiscard]] std::optional<VertexTransfer> loadTransfer(const std::string& path, std::uint64_t key,
                                                         std::size_t vertices, int bands, Diagnostics& diagnostics);

struct CachedTransfer {
  VertexTransfer transfer;
  bool fromCache = false;
  std::string path;      // the cache file
  TransferStats stats;   // of the precompute (zero when read from the cache)
};
// The transfer of `mesh` from the cache, or computed (building the Embree tracer only then,
// and only when shadowed) and saved. An empty `directory` uses defaultTransferCacheDirectory().
[[nodiscard]] CachedTransfer cachedTransfer(const TransferMesh& mesh, const TransferOptions& settings,
                                            const std::string& directory, Diagnostics& diagnostics,
                                            const TransferProgress& progress = {});

}  // namespace marionette::prt
