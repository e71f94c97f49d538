// BML/ParseSchedule: parse + schedule a typical block of 10 behaviors with
// speech (two word marks) and 4 cross references. Target: at most 20 us per block.
// BML/Parse: the same block parsed alone (parseBlock: the XML parser and the walk over its
// tree), to compare XML parsers (MARIONETTE_BML_XML).
// BML/Perform: the same block through the Realizer (composition, 10 requests on
// the character's timeline, predictions), then interrupted; the ratio of the two
// is what the realizer adds.
#include <benchmark/benchmark.h>

#include "marionette/bml/realizer.hpp"
#include "synthetic_rig.hpp"
#ifdef MARIONETTE_HAS_TTS
#include "marionette/tts_espeak/espeak_backend.hpp"
#endif

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

static void BmlParse(benchmark::State& state) {
  std::size_t behaviors = 0;
  for (auto _ : state) {
    marionette::bml::ParseResult r = marionette::bml::parseBlock(kTypicalBlock);
    behaviors = r.block ? r.block->behaviors.size() : 0;
    benchmark::DoNotOptimize(r);
  }
  if (behaviors != 10) state.SkipWithError("the typical block did not parse into 10 behaviors");
}
BENCHMARK(BmlParse)->Name("BML/Parse/typical10")->Unit(benchmark::kMicrosecond);

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

#ifdef MARIONETTE_HAS_TTS
// BML/PerformNewLine/{inline,background}: what perform() costs the calling (frame)
// thread for a block whose line has not been said: 1000 characters for espeak-ng, a new
// text each time. Inline says it in the call; Background hands it to the speech
// service's thread and returns (the block starts at a later update). The synthesis
// is drained outside the timed part.
static void BmlPerformNewLine(benchmark::State& state) {
  marionette::Scene scene;
  marionette::speech::useEspeak(scene.speech());  // a scene has no synthesizer of its own (issue 23)
  scene.addCharacter("robot", marionette::test::makeSyntheticRig());
  marionette::bml::Realizer realizer(scene);
  realizer.setForwardWarningsToScene(false);
  const bool background = state.range(0) != 0;
  realizer.setSpeechSynthesis(background ? marionette::bml::Realizer::SpeechSynthesis::Background
                                         : marionette::bml::Realizer::SpeechSynthesis::Inline);
  std::string words;
  while (words.size() < 980) words += "We keep talking about the weather, and nobody minds. ";
  static long line = 0;  // across repetitions too: espeak-ng keeps its last results process-wide
  for (auto _ : state) {
    const std::string block = "<bml id='b'><speech id='s'><text>Line " + std::to_string(++line) + ". " + words +
                              "</text></speech></bml>";
    marionette::bml::Schedule s = realizer.perform(block, "robot");
    benchmark::DoNotOptimize(s);
    state.PauseTiming();
    realizer.waitForSpeech();
    const auto* entry = scene.findCharacter("robot")->behaviors().find("b:s");
    if (s.failed || !entry || !entry->as<marionette::SpeechState>() || entry->request.end() - entry->request.start() < 30.0) {
      state.SkipWithError("the line was not said (a failed block, or no espeak-ng)");
      break;
    }
    realizer.interrupt("b");
    scene.update(0.0);
    state.ResumeTiming();
  }
}
// A fixed count: the untimed synthesis would otherwise run for thousands of iterations.
BENCHMARK(BmlPerformNewLine)->Name("BML/PerformNewLine")->ArgName("background")->Arg(0)->Arg(1)->Iterations(30)->Unit(benchmark::kMillisecond);
#endif
