// BML/ParseSchedule: parse + schedule a typical block of 10 behaviors with
// speech (two word marks) and 4 cross references. Target: at most 20 us per block.
// BML/Perform: the same block through the Realizer (composition, 10 requests on
// the character's timeline, predictions), then interrupted; the ratio of the two
// is what the realizer adds.
#include <benchmark/benchmark.h>

#include "marionette/bml/realizer.hpp"
#include "synthetic_rig.hpp"

namespace {
const char* kTypicalBlock = R"(<bml xmlns="http://www.bml-initiative.org/bml/bml-1.0" id="greeting" characterId="robot">
  <speech id="s1"><text>Hello there, <sync id="w1"/>nice to see you <sync id="w2"/>again today.</text></speech>
  <gesture id="g1" lexeme="BEAT" stroke="s1:w1"/>
  <head id="h1" lexeme="NOD" start="s1:w2"/>
  <gaze id="z1" target="user" start="0" end="s1:end+0.5"/>
  <faceLexeme id="f1" lexeme="RAISE_BROWS" start="g1:stroke-0.2"/>
  <posture id="p1" lexeme="STAND" start="0"/>
  <gesture id="g2" lexeme="WAVE" start="3"/>
  <headDirectionShift id="d1" target="user" start="1"/>
  <locomotion id="l1" target="door" start="6"/>
  <wait id="w" start="2" end="4"/>
</bml>)";
}  // namespace

static void BmlParseSchedule(benchmark::State& state) {
  std::size_t behaviors = 0;
  for (auto _ : state) {
    marionette::bml::Schedule s = marionette::bml::scheduleText(kTypicalBlock);
    behaviors = s.behaviors.size();
    benchmark::DoNotOptimize(s);
  }
  if (behaviors != 10) state.SkipWithError("the typical block did not schedule all 10 behaviors");
  state.counters["behaviors"] = static_cast<double>(behaviors);
}
BENCHMARK(BmlParseSchedule)->Name("BML/ParseSchedule/typical10")->Unit(benchmark::kMicrosecond);

static void BmlPerform(benchmark::State& state) {
  marionette::Scene scene;
  scene.addCharacter("robot", marionette::test::makeSyntheticRig());
  marionette::bml::Realizer realizer(scene);
  realizer.setSpeechSynthesis(marionette::bml::Realizer::SpeechSynthesis::Inline);  // the schedule at once: these tests read it
  realizer.setForwardWarningsToScene(false);
  std::size_t behaviors = 0;
  for (auto _ : state) {
    marionette::bml::Schedule s = realizer.perform(kTypicalBlock);
    behaviors = s.behaviors.size();
    realizer.interrupt("greeting");
    scene.update(0.0);  // prunes the interrupted requests
    benchmark::DoNotOptimize(s);
  }
  if (behaviors != 10) state.SkipWithError("the typical block did not schedule all 10 behaviors");
}
BENCHMARK(BmlPerform)->Name("BML/Perform/typical10")->Unit(benchmark::kMicrosecond);
