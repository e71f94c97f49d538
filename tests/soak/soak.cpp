// marionette_soak [FRAMES]: several characters driven by repeated BML blocks (speech,
// gaze, locomotion, head, gestures) for FRAMES frames at 60 Hz (default 10^6, 4.6 hours
// of scene time). Checks every frame that each transform buffer is finite, that the
// clock does not drift from frames x dt, and that the resident memory stays flat after
// warm-up. Prints a table (docs/reliability.md); exit 1 when a check fails.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "marionette/bml/realizer.hpp"
#include "marionette/speech/recorded_speech.hpp"
#include "real_rig.hpp"
#include "test_data.hpp"

using namespace marionette;

namespace {

double residentMiB() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

constexpr const char* kArcticText = "He turned sharply, and faced Gregson across the table.";

// The n-th block a character gets: a cycle of the behaviors the realizer drives.
std::string block(int n, bool speaks) {
  const std::string id = "b" + std::to_string(n);
  const double x = double(n % 7) - 3.0, z = 2.0 + double(n % 3);
  switch (n % 5) {
    case 0:
      return "<bml id='" + id + "'><gaze id='g' target='" + std::to_string(x) + " 1.5 " + std::to_string(z) +
             "' influence='NECK'/><head id='h' lexeme='NOD' start='g:ready'/></bml>";
    case 1:  // Godette has no walk clip: she looks instead
      return speaks ? "<bml id='" + id + "'><gaze id='g' target='" + std::to_string(x) + " 1.6 4'/></bml>"
                    : "<bml id='" + id + "'><locomotion id='l' target='" + std::to_string(x) + " " + std::to_string(z) +
                          "'/></bml>";
    case 2:
      return speaks ? "<bml id='" + id + "'><speech id='s'><text>He turned sharply, and <sync id='w4'/> faced Gregson " +
                          "across the table.</text></speech><head id='h' lexeme='SHAKE' start='s:w4'/></bml>"
                    : "<bml id='" + id + "'><head id='h' lexeme='TILT'/></bml>";
    case 3:
      return "<bml id='" + id + "'><faceLexeme id='f' lexeme='" + (speaks ? "SMILE" : "SURPRISE") +
             "' amount='0.6'/><head id='h' lexeme='NOD'/></bml>";
    default:
      return "<bml id='" + id + "'>" + (speaks ? "" : "<locomotion id='l' target='0 0'/>") +
             "<gaze id='g' target='0 1.6 5'/></bml>";
  }
}

}  // namespace

int main(int argc, char** argv) {
  const long frames = argc > 1 ? std::atol(argv[1]) : 1000000;
  const std::string robot = test::sharedAsset("characters/RobotExpressive.glb");
  const std::string godette = test::sharedAsset("characters/Godette_vrm_v4.vrm");
  Scene scene;
  auto recorded = std::make_shared<speech::RecordedSpeech>();
  if (const std::string e = recorded->addLine(kArcticText, test::sharedAsset("speech/arctic_a0009.wav"),
                                              test::sharedAsset("speech/arctic_a0009.phones.txt"));
      !e.empty()) {
    std::fprintf(stderr, "soak: %s\n", e.c_str());
    return 2;
  }
  scene.speech().addBackend(recorded);
  scene.speech().useDefaultSynthesizer(false);  // the recorded line only: the same work every time
  struct Driven {
    Character* character;
    bool speaks;
  };
  std::vector<Driven> cast;
  for (int i = 0; i < 4; ++i) {
    const bool isGodette = i % 2 == 1;
    auto rig = test::loadRigWithProfile(isGodette ? godette : robot, isGodette ? "Godette_vrm_v4.json" : "RobotExpressive.json");
    if (!rig) return 2;
    Character* c = scene.addCharacter("c" + std::to_string(i), rig);
    c->setPosition({float(i) * 1.5f - 2.25f, 0.0f, 0.0f});
    cast.push_back({c, isGodette});
  }
  bml::Realizer realizer(scene);
  long warnings = 0;
  std::vector<std::string> firstWarnings;  // printed: what the realizer could not do
  realizer.addFeedbackListener([&](const bml::Feedback& f) {
    if (f.kind != bml::Feedback::Kind::Warning) return;
    if (++warnings <= 5) firstWarnings.push_back(f.character + " " + f.blockId + ":" + f.behaviorId + ": " + f.warning.message);
  });
  const double dt = 1.0 / 60.0;
  double rssWarm = 0.0, rssMax = 0.0, worstDrift = 0.0;
  long nonFinite = 0, blocks = 0, refused = 0;
  const auto started = std::chrono::steady_clock::now();
  std::printf("| frames | scene time (s) | RSS (MiB) | blocks sent | clock drift (s) |\n|---|---|---|---|---|\n");
  for (long f = 1; f <= frames; ++f) {
    if (f % 180 == 1)  // every 3 s a new block for one character, in turn
      for (std::size_t k = 0; k < cast.size(); ++k)
        if ((f / 180) % cast.size() == k) {
          const bml::Schedule s = realizer.perform(block(int(blocks), cast[k].speaks), cast[k].character->name());
          refused += s.failed;
          ++blocks;
        }
    scene.update(dt);
    realizer.update();
    for (const Driven& d : cast) {
      float sum = 0.0f;
      for (float v : d.character->transformBuffer().skinning()) sum += v;
      nonFinite += !std::isfinite(sum);
    }
    // The clock is a double sum of dt: compare with frames x dt (an exact product).
    worstDrift = std::max(worstDrift, std::abs(scene.time() - double(f) * dt));
    if (f == 20000) rssWarm = residentMiB();
    if (f % 100000 == 0 || f == frames) {
      const double rss = residentMiB();
      rssMax = std::max(rssMax, rss);
      std::printf("| %ld | %.0f | %.1f | %ld | %.2e |\n", f, scene.time(), rss, blocks, worstDrift);
      std::fflush(stdout);
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::printf("\n%ld frames of %zu characters in %.1f s (%.1f us a frame), %ld BML blocks (%ld refused), "
              "%ld warning feedbacks, %ld non-finite buffers, RSS %.1f MiB after 20000 frames and at most %.1f MiB "
              "after, clock drift at most %.2e s\n",
              frames, cast.size(), seconds, 1e6 * seconds / double(frames), blocks, refused, warnings, nonFinite,
              rssWarm, rssMax, worstDrift);
  for (const std::string& w : firstWarnings) std::printf("  warning: %s\n", w.c_str());
  const bool flat = rssWarm == 0.0 || rssMax <= rssWarm * 1.05 + 2.0;
  const bool ok = nonFinite == 0 && refused == 0 && flat && worstDrift < 1e-6 * std::max(1.0, double(frames) * dt);
  if (!ok) std::printf("soak: FAILED (%s%s%s%s)\n", nonFinite ? "non-finite output " : "", refused ? "refused blocks " : "",
                       flat ? "" : "memory grew ", worstDrift < 1e-6 * double(frames) * dt ? "" : "clock drift");
  return ok ? 0 : 1;
}
