// libFuzzer target: BML parser + scheduler + realizer on arbitrary bytes. Built
// and run by scripts/fuzz bml (clang). Any crash it finds is kept as a
// regression test in tests/bml/.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "marionette/bml/realizer.hpp"

namespace {
// A two-joint character with a clip named BEAT, so gestures reach the clip controller.
std::shared_ptr<const marionette::Rig> fuzzRig() {
  using namespace marionette;
  auto asset = std::make_shared<Asset>();
  asset->skeleton.addJoint("root", -1, Transform{});
  Transform arm;
  arm.translation = {0, 1, 0};
  asset->skeleton.addJoint("arm", 0, arm);
  Clip beat;
  beat.name = "BEAT";
  JointTrack t;
  t.joint = 1;
  t.rotation.times = {0.0f, 0.5f};
  t.rotation.values = {glm::quat(1, 0, 0, 0), glm::angleAxis(1.0f, glm::vec3(0, 0, 1))};
  beat.tracks.push_back(t);
  beat.updateDuration();
  asset->clips.push_back(beat);
  return std::make_shared<Rig>(*asset);
}

// <bmlt:audiofile fileName>: "a.wav" is 0.1 s of 8 kHz 8-bit silence; any other name reads
// the input itself as a WAV. Nothing comes from the disk.
bool fuzzFiles(std::string_view input, const std::string& path, std::string& bytes) {
  if (path != "a.wav") {
    bytes.assign(input);
    return true;
  }
  static const std::string wav = [] {
    auto le = [](std::uint32_t v, int n) {
      std::string s;
      for (int i = 0; i < n; ++i) s += static_cast<char>(v >> (8 * i));
      return s;
    };
    return "RIFF" + le(36 + 800, 4) + "WAVEfmt " + le(16, 4) + le(1, 2) + le(1, 2) + le(8000, 4) + le(8000, 4) +
           le(1, 2) + le(8, 2) + "data" + le(800, 4) + std::string(800, '\x80');
  }();
  bytes = wav;
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace marionette;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const bml::Schedule s = bml::scheduleText(text);
  // The contract: every scheduled time is finite and every behavior is in order.
  for (const auto& b : s.behaviors)
    for (std::size_t k = 0; k < b.syncs.size(); ++k) {
      if (!std::isfinite(b.syncs[k].time)) __builtin_trap();
      if (k > 0 && b.syncs[k].time < b.syncs[k - 1].time - 1e-6) __builtin_trap();
    }
  // Realized twice (the second block refers to, appends to or replaces the first)
  // on a character for a few frames: poses stay finite.
  static const auto rig = fuzzRig();
  Scene scene;
  Character* c = scene.addCharacter("c", rig);
  scene.setObject("camera", {0.0f, 1.6f, 3.0f});  // targets scripts name (issue 24)
  bml::Realizer realizer(scene);
  realizer.setFiles([text](const std::string& path, std::string& bytes, std::string&) { return fuzzFiles(text, path, bytes); });
  realizer.perform(text);
  scene.update(0.25);
  realizer.update();
  realizer.perform(text);
  for (double dt : {0.0, 0.1, 1.0, 5.0}) {
    scene.update(dt);
    realizer.update();
    for (const Transform& t : c->localPose())
      if (!std::isfinite(t.rotation.w) || !std::isfinite(t.translation.x)) __builtin_trap();
  }
  // Read as SmartBody's (ids generated, z-up targets), and a preplanned block activated.
  realizer.setDialect("c", bml::Dialect::SmartBody);
  const bml::Schedule sbm = realizer.perform(text);
  if (sbm.preplanned) realizer.activate(sbm.blockId);
  for (double dt : {0.1, 2.0}) {
    scene.update(dt);
    realizer.update();
    for (const Transform& t : c->localPose())
      if (!std::isfinite(t.rotation.w) || !std::isfinite(t.translation.x)) __builtin_trap();
  }
  return 0;
}
