// Builds a one-joint rig, plays nothing, updates once: proves headers, library
// and dependencies come through find_package(marionette); and the C API when the package has it.
#include <cstdio>
#include <memory>

#include <marionette/scene/scene.hpp>

#ifdef CONSUMER_HAS_C_API
extern "C" int c_consumer_ok(void);
#endif

int main() {
  auto asset = std::make_shared<marionette::Asset>();
  asset->skeleton.addJoint("root", -1, marionette::Transform{});
  marionette::Scene scene;
  auto* c = scene.addCharacter("one", std::make_shared<marionette::Rig>(*asset));
  scene.update(1.0 / 60.0);
  bool ok = c && c->transformBuffer().frame() == 1 && c->transformBuffer().skinning().size() == 16;
#ifdef CONSUMER_HAS_C_API
  ok = ok && c_consumer_ok();
#endif
  std::printf("consumer: %s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
