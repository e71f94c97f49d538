// The native side of the web trace (tests/web/README.md): plays trace_scenario.json through
// the C API, as bridge/web/js/marionette.mjs does in the browser, and writes every character's
// bone world matrices (world * model-space joint matrix, column-major, float32) for every frame.
//   marionette_web_trace_native SCENARIO SHARED_ASSETS_DIR OUT.bin
//   marionette_web_trace_native --bench N FRAMES CHARACTER_FILE   (docs/benchmarks.md, scripts/bench-web)
// OUT.bin: for each frame, for each character in the scenario's order, joint_count * 16 floats.
// Also prints the update cost per frame (median of the frames, microseconds).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "marionette/marionette.h"

namespace {

int failWith(mn_scene* scene, const std::string& what) {
  std::fprintf(stderr, "native_trace: %s: %s\n", what.c_str(), mn_scene_last_error(scene));
  return 1;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

// --bench N FRAMES ASSET: N copies of a character (its "Idle" clip looping, a gaze at the
// camera), FRAMES updates at 60 Hz after at least 1.5 s of warm-up; prints the update cost per character
// (the median of 5 runs of FRAMES/5 updates each), as bench_runner.mjs measures it in the page.
int bench(int n, int frames, const std::string& file) {
  const std::string bytes = readFile(file);
  mn_asset* asset = nullptr;
  const std::string hint = file.substr(file.find_last_of('/') + 1);
  if (mn_asset_load_memory(bytes.data(), bytes.size(), hint.c_str(), nullptr, &asset) != MN_OK)
    return failWith(nullptr, "asset " + file);
  mn_scene* scene = nullptr;
  mn_scene_create(&scene);
  mn_scene_set_speech_synthesis(scene, MN_SPEECH_INLINE);
  mn_scene_set_object(scene, "camera", 0.0f, 1.5f, 6.0f);
  for (int k = 0; k < n; ++k) {
    const std::string name = "c" + std::to_string(k);
    mn_character* c = nullptr;
    if (mn_scene_add_character_from_asset(scene, name.c_str(), asset, &c) != MN_OK) return failWith(scene, "character");
    mn_character_set_position(c, static_cast<float>(k % 10) - 4.5f, 0.0f, -static_cast<float>(k / 10));
    mn_character_play(c, 0, "Idle", nullptr);
    const std::string bml = "<bml id=\"b" + name + "\" characterId=\"" + name + "\"><gaze id=\"g\" target=\"camera\"/></bml>";
    if (mn_scene_send_bml(scene, nullptr, bml.c_str()) != MN_OK) return failWith(scene, "bml");
  }
  mn_asset_release(asset);
  const auto warm = std::chrono::steady_clock::now();  // as long as the page warms up (bench_runner.mjs)
  for (int f = 0; f < 60 || std::chrono::steady_clock::now() - warm < std::chrono::milliseconds(1500); ++f)
    mn_scene_update(scene, 1.0 / 60.0);
  std::vector<double> perCharacter;
  for (int run = 0; run < 5; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = 0; f < frames / 5; ++f) mn_scene_update(scene, 1.0 / 60.0);
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    perCharacter.push_back(us / (frames / 5) / n);
  }
  std::sort(perCharacter.begin(), perCharacter.end());
  std::printf("{\"characters\": %d, \"frames\": %d, \"usPerCharacter\": %.3f}\n", n, frames, perCharacter[2]);
  mn_scene_destroy(scene);
  return 0;
}

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--bench") return bench(std::atoi(argv[2]), std::atoi(argv[3]), argv[4]);
  if (argc != 4) {
    std::fprintf(stderr, "usage: marionette_web_trace_native SCENARIO SHARED_ASSETS_DIR OUT.bin\n");
    return 2;
  }
  const nlohmann::json spec = nlohmann::json::parse(readFile(argv[1]));
  const std::string assets = std::string(argv[2]) + "/";
  mn_scene* scene = nullptr;
  if (mn_scene_create(&scene) != MN_OK) return failWith(nullptr, "mn_scene_create");
  mn_scene_set_speech_synthesis(scene, MN_SPEECH_INLINE);  // as the web build (no threads)
  for (const auto& [name, p] : spec["objects"].items())
    if (mn_scene_set_object(scene, name.c_str(), p[0], p[1], p[2]) != MN_OK) return failWith(scene, "object " + name);
  for (const auto& line : spec["speechLines"]) {
    const std::string audio = assets + line["audio"].get<std::string>();
    const std::string alignment = assets + line["alignment"].get<std::string>();
    if (mn_scene_add_speech_line(scene, line["text"].get<std::string>().c_str(), audio.c_str(), alignment.c_str(), nullptr,
                                 nullptr) != MN_OK)
      return failWith(scene, "speech line");
  }
  std::vector<mn_character*> characters;
  std::vector<std::vector<float>> palettes;
  for (const auto& c : spec["characters"]) {
    const std::string file = c["file"].get<std::string>();
    const std::string bytes = readFile(assets + file);
    mn_asset* asset = nullptr;
    const std::string hint = file.substr(file.find_last_of('/') + 1);
    if (mn_asset_load_memory(bytes.data(), bytes.size(), hint.c_str(), nullptr, &asset) != MN_OK)
      return failWith(nullptr, "asset " + file);
    mn_character* character = nullptr;
    if (mn_scene_add_character_from_asset(scene, c["name"].get<std::string>().c_str(), asset, &character) != MN_OK)
      return failWith(scene, "character");
    mn_asset_release(asset);
    const auto& p = c["position"];
    mn_character_set_position(character, p[0], p[1], p[2]);
    characters.push_back(character);
    palettes.emplace_back(mn_character_joint_count(character) * 16);
  }
  const int frames = spec["frames"].get<int>();
  const double dt = spec["dt"].get<double>();
  std::ofstream out(argv[3], std::ios::binary);
  std::vector<double> micros;
  std::vector<float> world(16);
  for (int frame = 0; frame < frames; ++frame) {
    for (std::size_t k = 0; k < characters.size(); ++k)
      for (const auto& b : spec["characters"][k]["bml"])
        if (b["frame"].get<int>() == frame &&
            mn_scene_send_bml(scene, nullptr, b["text"].get<std::string>().c_str()) != MN_OK)
          return failWith(scene, "bml at frame " + std::to_string(frame));
    const auto t0 = std::chrono::steady_clock::now();
    if (mn_scene_update(scene, dt) != MN_OK) return failWith(scene, "update");
    micros.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    for (std::size_t k = 0; k < characters.size(); ++k) {
      std::vector<float>& palette = palettes[k];
      mn_character_palette(characters[k], MN_PALETTE_MAT4_COLUMN_MAJOR, 0, palette.data(), palette.size());
      mn_character_world_matrix(characters[k], world.data());
      for (std::size_t j = 0; j * 16 < palette.size(); ++j) {  // world * model, column-major
        float m[16];
        for (int col = 0; col < 4; ++col)
          for (int row = 0; row < 4; ++row) {
            float s = 0.0f;
            for (int i = 0; i < 4; ++i) s += world[i * 4 + row] * palette[j * 16 + col * 4 + i];
            m[col * 4 + row] = s;
          }
        out.write(reinterpret_cast<const char*>(m), sizeof m);
      }
    }
  }
  std::nth_element(micros.begin(), micros.begin() + micros.size() / 2, micros.end());
  std::printf("native_trace: %d frames, %zu characters, median update %.1f us\n", frames, characters.size(),
              micros[micros.size() / 2]);
  mn_scene_destroy(scene);
  return out ? 0 : 1;
}
