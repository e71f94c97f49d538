// The README's embedding example, compiled and run by the tests so it stays true.
//   minimal_embedding CHARACTER_FILE [CLIP]
// Loads a character, plays a clip on one character for one second at 60 Hz and
// copies its transform buffer into an engine-side palette, as an engine would.
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <marionette/io/import.hpp>
#include <marionette/scene/scene.hpp>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CHARACTER_FILE [CLIP]\n", argv[0]);
    return 2;
  }
  auto imported = marionette::importAsset(argv[1]);
  if (!imported.ok()) {
    std::cerr << imported.diagnostics.format();
    return 2;
  }
  auto rig = std::make_shared<marionette::Rig>(*imported.asset);  // copies what the runtime needs

  marionette::Scene scene;  // several scenes may coexist
  auto* robot = scene.addCharacter("robot", rig);
  const char* clip = argc > 2 ? argv[2] : (rig->clips().empty() ? "" : rig->clips().front()->clip.name.c_str());
  if (*clip && !robot->play(0, clip, {.rootMotion = true})) {
    std::fprintf(stderr, "no clip named '%s'\n", clip);
    return 2;
  }
  // A timed behavior without BML: the last clip as a gesture over the first clip,
  // blending in until "ready" and out from "relax".
  const std::string gestureClip = rig->clips().size() > 1 ? rig->clips().back()->clip.name : "";
  if (!gestureClip.empty()) {
    const double t = scene.time();
    marionette::BehaviorRequest wave{.id = "wave1", .kind = marionette::BehaviorKind::Gesture,
                                     .syncs = {{"start", t}, {"ready", t + 0.3}, {"relax", t + 0.7}, {"end", t + 1.0}},
                                     .clip = gestureClip};
    if (!robot->addBehavior(std::move(wave)).realized) return 2;
  }
  std::vector<float> enginePalette(robot->transformBuffer().skinning().size());
  for (int frame = 0; frame < 60; ++frame) {
    scene.update(1.0 / 60.0);  // no allocation, no exceptions after warm-up
    const auto& buffer = robot->transformBuffer();  // skinning(): N x 16 floats, column-major
    std::memcpy(enginePalette.data(), buffer.skinning().data(), enginePalette.size() * sizeof(float));
  }
  std::printf("%s: %zu joints, frame %llu, clip '%s', gesture '%s', palette[0..3] = %.3f %.3f %.3f %.3f\n", argv[1],
              robot->skeleton().jointCount(), static_cast<unsigned long long>(robot->transformBuffer().frame()), clip,
              gestureClip.c_str(),
              enginePalette[0], enginePalette[1], enginePalette[2], enginePalette[3]);
  return 0;
}
