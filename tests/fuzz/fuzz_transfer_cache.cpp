// libFuzzer target: PRT transfer cache files (prt/transfer_cache.hpp), read by
// prt::loadTransfer from a temporary file, once with the key, vertex count and bands of
// the seed's mesh and once with those the file's own header claims (as a caller with
// another mesh would). Contract: no crash, no allocation beyond what the caller expects;
// a refused file gives a warning naming it; a transfer read has the size asked for,
// finite coefficients and occlusion in [0, 1]. With MARIONETTE_FUZZ_WRITE_SEED=folder
// the program writes a valid cache file there with saveTransfer (the unshadowed transfer
// of a tetrahedron) and exits (scripts/fuzz seeds the corpus so). Built by scripts/fuzz.
#include <cstring>

#include "fuzz_support.hpp"
#include "marionette/prt/transfer_cache.hpp"
#include "marionette/prt/transfer_mesh.hpp"

using namespace marionette;
using fuzz::require;

namespace {

constexpr int kBands = 3;

prt::TransferMesh tetrahedron() {
  prt::TransferMesh m;
  m.positions = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
  for (const glm::vec3& p : m.positions) m.normals.push_back(glm::normalize(p));
  m.indices = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
  return m;
}

prt::TransferOptions settings() {
  prt::TransferOptions s;
  s.bands = kBands;
  s.shadowed = false;
  s.threads = 1;
  return s;
}

void check(const std::string& path, std::uint64_t key, std::size_t vertices, int bands) {
  Diagnostics d;
  const auto t = prt::loadTransfer(path, key, vertices, bands, d);
  require(fuzz::allName(d, path), "a diagnostic does not name the file");
  if (!t) {
    require(!d.items.empty(), "a refused cache file gives no warning");
    return;
  }
  require(t->bands == bands, "bands differ from the request");
  require(t->coefficients.size() == vertices * static_cast<std::size_t>(bands * bands), "coefficient count");
  require(t->occluded.size() == vertices, "occlusion count");
  require(fuzz::finiteAll(t->coefficients), "coefficients not finite");
  for (float o : t->occluded) require(o >= 0.0f && o <= 1.0f, "occlusion outside [0, 1]");
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = std::getenv("MARIONETTE_FUZZ_WRITE_SEED")) {
    const prt::TransferMesh mesh = tetrahedron();
    Diagnostics d;
    const prt::VertexTransfer t = prt::computeTransfer(mesh, settings(), nullptr, d);
    const bool ok = t.bands == kBands &&
                    prt::saveTransfer(std::string(dir) + "/tetrahedron.mprt", prt::transferCacheKey(mesh, settings()),
                                      settings(), t, d);
    if (!ok) std::fprintf(stderr, "cannot write the seed: %s", d.format().c_str());
    std::exit(ok ? 0 : 1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::uint64_t key = prt::transferCacheKey(tetrahedron(), settings());
  const std::string path = fuzz::writeInput(data, size, "in.mprt");
  check(path, key, 4, kBands);
  // The header's own claims (magic 8, key 8, bands 4, shadowed 4, vertices 8), within what a
  // real caller could ask for: bands 2..8, vertices up to the file's size.
  if (size >= 32) {
    std::uint64_t claimedKey = 0, vertices = 0;
    std::uint32_t bands = 0;
    std::memcpy(&claimedKey, data + 8, 8);
    std::memcpy(&bands, data + 16, 4);
    std::memcpy(&vertices, data + 24, 8);
    if (bands >= 2 && bands <= 8 && vertices <= size) check(path, claimedKey, vertices, static_cast<int>(bands));
  }
  return 0;
}
