// Builds a one-joint rig, plays nothing, updates once: proves headers, library
// and dependencies come through find_package(marionette); a glTF from memory whose
// buffer comes through a FileReader; and the C API when the package has it.
#include <cstdio>
#include <memory>
#include <string>

#include <marionette/io/import.hpp>
#include <marionette/scene/scene.hpp>

#ifdef CONSUMER_HAS_C_API
extern "C" int c_consumer_ok(void);
#endif

int main() {
  auto asset = std::make_shared<marionette::Asset>();
  asset->skeleton.addJoint("root", -1, marionette::Transform{});
  marionette::Scene scene;
  const auto rig = std::make_shared<marionette::Rig>(*asset);
  auto* c = scene.addCharacter("one", rig);
  scene.update(1.0 / 60.0);
  bool ok = c && c->transformBuffer().frame() == 1 && c->transformBuffer().skinning().size() == 16;
  // The scene's work through the engine's parallel-for (here: serial, chunks backwards).
  for (int i = 0; i < 20; ++i) scene.addCharacter("more" + std::to_string(i), rig);
  static int chunks = 0;
  scene.setParallelFor(
      [](void*, marionette::Scene::ParallelTask task, void* context, int count) {
        for (int i = count - 1; i >= 0; --i, ++chunks) task(context, i);
      },
      nullptr);
  scene.update(1.0 / 60.0);
  ok = ok && chunks >= 2 && c->transformBuffer().frame() == 2;

  const std::string gltf =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
      R"("nodes":[{"name":"root","children":[1]},{"name":"tip"}],"buffers":[{"uri":"two.bin","byteLength":4}]})";
  int reads = 0;
  marionette::ImportOptions options;
  options.readFile = [&reads](const std::string& path, std::string& bytes, std::string&) {
    if (path != "pak/two.bin") return false;
    ++reads;
    bytes.assign(4, '\0');
    return true;
  };
  const marionette::ImportResult two = marionette::importAssetFromMemory(gltf, "pak/two.gltf", options);
  ok = ok && two.ok() && reads == 1 && two.asset->skeleton.jointCount() == 2;
  if (!two.ok()) std::fprintf(stderr, "%s\n", two.diagnostics.format().c_str());
#ifdef CONSUMER_HAS_C_API
  ok = ok && c_consumer_ok();
#endif
  std::printf("consumer: %s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
