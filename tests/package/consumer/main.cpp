// Builds a one-joint rig, plays nothing, updates once: proves headers, library
// and dependencies come through find_package(marionette).
#include <cstdio>
#include <memory>

#include <marionette/scene/scene.hpp>

int main() {
  auto asset = std::make_shared<marionette::Asset>();
  asset->skeleton.addJoint("root", -1, marionette::Transform{});
  marionette::Scene scene;
  auto* c = scene.addCharacter("one", std::make_shared<marionette::Rig>(asset));
  scene.update(1.0 / 60.0);
  const bool ok = c && c->transformBuffer().frame() == 1 && c->transformBuffer().skinning().size() == 16;
  std::printf("consumer: %s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
