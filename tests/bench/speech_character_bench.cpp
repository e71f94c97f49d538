// marionette_bench: what a speaking character costs per frame.
//   Speech/GodetteFrame/speaking:0|1   100 Godettes (VRM, 68 joints) updated one frame
//                           at a time, silent (0) or each saying the recorded
//                           arctic_a0009 line (1) with lip-sync on her mouth shapes.
//                           Counter us_per_char: wall time per character per frame.
//                           A new line is queued outside the timed part as one ends.
//                           The speaking cost is the difference of the two, measured
//                           in one run (the target: at most 0.5 us).
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "marionette/io/import.hpp"
#include "marionette/scene/scene.hpp"
#include "marionette/speech/recorded_speech.hpp"
#include "test_data.hpp"

using namespace marionette;

namespace {

constexpr int kCharacters = 100;
constexpr const char* kLine = "He turned sharply, and faced Gregson across the table.";

std::shared_ptr<const Rig> godette(benchmark::State& state) {
  static std::shared_ptr<const Rig> rig = [] {
    ImportResult r = importAsset(test::sharedAsset("characters/Godette_vrm_v4.vrm"));
    return r.ok() ? std::make_shared<const Rig>(*r.asset) : nullptr;
  }();
  if (!rig) state.SkipWithError("cannot load ../shared/assets/characters/Godette_vrm_v4.vrm");
  return rig;
}

void BM_GodetteFrame(benchmark::State& state) {
  const auto rig = godette(state);
  if (!rig) return;
  Scene scene;
  auto recorded = std::make_shared<speech::RecordedSpeech>();
  if (std::string e = recorded->addLine(kLine, test::sharedAsset("speech/arctic_a0009.wav"),
                                        test::sharedAsset("speech/arctic_a0009.phones.txt"));
      !e.empty()) {
    state.SkipWithError(e.c_str());
    return;
  }
  scene.speech().addBackend(recorded);
  const bool speaking = state.range(0) != 0;
  constexpr double kLineSeconds = 49520.0 / 16000.0;
  std::vector<Character*> characters;
  for (int i = 0; i < kCharacters; ++i) characters.push_back(scene.addCharacter("g" + std::to_string(i), rig));
  // One line at a time, the next queued (outside the timed part) as one ends, as an engine would.
  int lines = 0;
  auto queueLine = [&] {
    const double start = lines * kLineSeconds;
    for (Character* c : characters) {
      BehaviorRequest r;
      r.id = "s" + std::to_string(lines);
      r.kind = BehaviorKind::Speech;
      r.parameters = SpeechParameters{.text = kLine};
      r.syncs = {{"start", start}, {"end", start + kLineSeconds}};
      if (!c->addBehavior(std::move(r)).realized) state.SkipWithError("the line was not realized");
    }
    ++lines;
  };
  if (speaking) queueLine(), queueLine();
  for (int f = 0; f < 10; ++f) scene.update(1.0 / 60.0);  // warm-up
  double seconds = 0.0;
  for (auto _ : state) {
    if (speaking && scene.time() > (lines - 1) * kLineSeconds) queueLine();
    const auto t0 = std::chrono::steady_clock::now();
    scene.update(1.0 / 60.0);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["us_per_char"] = 1e6 * seconds / (static_cast<double>(state.iterations()) * kCharacters);
}
BENCHMARK(BM_GodetteFrame)->Name("Speech/GodetteFrame")->ArgName("speaking")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
