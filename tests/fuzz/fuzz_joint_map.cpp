// libFuzzer target: joint maps (JSON, rig/joint_map.hpp), read by loadJointMap from a
// temporary file for each of the real glTF characters. Contract: no crash; every
// diagnostic names the file; the map holds joint indices of the skeleton only, no joint
// twice; and it survives jointMapJson: written out and read again, it is the same map.
// Built by scripts/fuzz.
#include <set>

#include "fuzz_support.hpp"
#include "marionette/rig/joint_map.hpp"

namespace {

using namespace marionette;
using fuzz::require;

void checkMap(const retarget::JointMap& m, const Skeleton& s) {
  const int n = static_cast<int>(s.jointCount());
  std::set<int> seen;
  auto joint = [&](int j) {
    require(j >= 0 && j < n, "joint index out of range");
    require(seen.insert(j).second, "a joint is mapped twice");
  };
  for (int j : m.bones)
    if (j != -1) joint(j);
  for (const auto& chain : m.chains)
    for (int j : chain) joint(j);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::writeInput(data, size, "in.jointmap.json");
  for (const Asset& asset : fuzz::realCharacters()) {
    const retarget::JointMapResult r = retarget::loadJointMap(path, asset);
    require(fuzz::allName(r.diagnostics, path), "a diagnostic does not name the file");
    if (!r.diagnostics.ok()) continue;
    checkMap(r.map, asset.skeleton);
    const std::string text = retarget::jointMapJson(r.map, asset.skeleton);
    const std::string again = fuzz::writeInput(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(),
                                               "again.jointmap.json");
    const retarget::JointMapResult back = retarget::loadJointMap(again, asset);
    require(back.diagnostics.ok(), "jointMapJson's output does not load");
    require(back.map.bones == r.map.bones && back.map.chains == r.map.chains, "jointMapJson does not round-trip");
  }
  return 0;
}
