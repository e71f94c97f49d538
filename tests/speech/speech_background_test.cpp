// The speech service's background synthesis (prepare): it returns at once, a
// request being said is said once however it is asked for, what is cached or over
// the limits is ready at once, and destroying the service leaves nothing waiting.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>

#include "gated_speech_backend.hpp"
#include "marionette/speech/recorded_speech.hpp"
#include "marionette/speech/speech_service.hpp"
#include "test_data.hpp"

namespace marionette {
namespace {

constexpr const char* kArcticText = "He turned sharply, and faced Gregson across the table.";

std::shared_ptr<test::GatedSpeechBackend> gatedArcticLine() {
  auto recorded = std::make_shared<speech::RecordedSpeech>();
  EXPECT_EQ(recorded->addLine(kArcticText, test::sharedAsset("speech/arctic_a0009.wav"),
                              test::sharedAsset("speech/arctic_a0009.phones.txt")),
            "");
  return std::make_shared<test::GatedSpeechBackend>(recorded);
}

speech::SpeechRequest line(const std::string& text) {
  speech::SpeechRequest r;
  r.text = text;
  return r;
}

// A service that asks only `backend` (no espeak-ng).
std::unique_ptr<speech::SpeechService> serviceWith(std::shared_ptr<speech::SpeechBackend> backend) {
  auto service = std::make_unique<speech::SpeechService>();
  service->useDefaultSynthesizer(false);
  service->addBackend(std::move(backend));
  return service;
}

void waitForCalls(const test::GatedSpeechBackend& gate, int calls) {
  while (gate.calls < calls) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

}  // namespace

TEST(SpeechBackground, PrepareReturnsAtOnceAndALineIsSaidOnce) {
  MARIONETTE_REQUIRE_FILE(test::sharedAsset("speech/arctic_a0009.wav"));
  auto gate = gatedArcticLine();
  const auto owned = serviceWith(gate);
  speech::SpeechService& service = *owned;
  const test::GateOpener opener{*gate};

  const auto prepared = service.prepare(line(kArcticText));
  ASSERT_NE(prepared, nullptr);
  EXPECT_FALSE(prepared->ready()) << "the synthesizer is still closed";
  EXPECT_EQ(service.preparing(), 1u);
  EXPECT_EQ(service.prepare(line(kArcticText)), prepared) << "asked again: the same preparation";
  waitForCalls(*gate, 1);

  // speak() of the line being prepared waits for it rather than saying it again.
  speech::SpeechService::Result spoken;
  std::thread speaker([&] { spoken = service.speak(line(kArcticText)); });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  gate->setOpen(true);
  speaker.join();
  service.waitUntilPrepared();
  ASSERT_TRUE(prepared->ready());
  ASSERT_TRUE(prepared->result().line) << prepared->result().error;
  EXPECT_EQ(spoken.line, prepared->result().line);
  EXPECT_EQ(gate->calls, 1);
  EXPECT_EQ(service.preparing(), 0u);

  // Cached now, and a request over the limits: both ready at once, neither said.
  EXPECT_TRUE(service.prepare(line(kArcticText))->ready());
  const auto refused = service.prepare(line(std::string(3000, 'a')));
  ASSERT_TRUE(refused->ready());
  EXPECT_EQ(refused->result().line, nullptr);
  EXPECT_NE(refused->result().error.find("kMaxSpeechCharacters"), std::string::npos) << refused->result().error;
  EXPECT_EQ(gate->calls, 1);
}

TEST(SpeechBackground, ALineThatFailsIsReadyWithTheReason) {
  MARIONETTE_REQUIRE_FILE(test::sharedAsset("speech/arctic_a0009.wav"));
  auto gate = gatedArcticLine();
  gate->setOpen(true);
  const auto owned = serviceWith(gate);
  speech::SpeechService& service = *owned;
  const auto prepared = service.prepare(line("Nobody recorded this."));
  service.waitUntilPrepared();
  ASSERT_TRUE(prepared->ready());
  EXPECT_EQ(prepared->result().line, nullptr);
  EXPECT_NE(prepared->result().error.find("gated"), std::string::npos) << prepared->result().error;
}

TEST(SpeechBackground, DestroyingTheServiceFinishesTheLineBeingSaidAndDropsTheQueued) {
  MARIONETTE_REQUIRE_FILE(test::sharedAsset("speech/arctic_a0009.wav"));
  auto gate = gatedArcticLine();
  auto service = serviceWith(gate);
  const auto first = service->prepare(line(kArcticText));
  waitForCalls(*gate, 1);  // the service's thread is saying it
  const auto queued = service->prepare(line("Queued behind it."));
  std::thread opener([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    gate->setOpen(true);
  });
  service.reset();  // waits for the first line, not for the queued one
  opener.join();
  ASSERT_TRUE(first->ready() && queued->ready());
  EXPECT_NE(first->result().line, nullptr) << first->result().error;
  EXPECT_EQ(queued->result().line, nullptr);
  EXPECT_NE(queued->result().error.find("destroyed"), std::string::npos) << queued->result().error;
  EXPECT_EQ(gate->calls, 1);
}

// A backend that throws, or fails until it learns a line: the service neither hangs nor
// remembers a failure (a line a backend learns later is said when asked again).
class MoodyBackend final : public speech::SpeechBackend {
 public:
  std::string_view name() const noexcept override { return "moody"; }
  speech::SpeechResult synthesize(const speech::SpeechRequest& request) override {
    ++calls;
    if (request.text == "throw") throw std::runtime_error("the synthesizer fell over");
    if (!knows) return {nullptr, "no such line yet"};
    auto u = std::make_shared<speech::Utterance>();
    u->text = request.text;
    u->duration = 0.5;
    return {u, {}};
  }
  std::atomic<int> calls{0};
  std::atomic<bool> knows{false};
};

TEST(SpeechBackground, ABackendThatThrowsFailsTheLineAndNothingWaitsForever) {
  auto moody = std::make_shared<MoodyBackend>();
  const auto owned = serviceWith(moody);
  speech::SpeechService& service = *owned;
  const auto thrown = service.prepare(line("throw"));
  service.waitUntilPrepared();  // returns: the line is ready, with the reason
  ASSERT_TRUE(thrown->ready());
  EXPECT_EQ(thrown->result().line, nullptr);
  EXPECT_NE(thrown->result().error.find("the synthesizer fell over"), std::string::npos) << thrown->result().error;
  const speech::SpeechService::Result inline_ = service.speak(line("throw"));  // in the caller's thread: no throw
  EXPECT_NE(inline_.error.find("fell over"), std::string::npos) << inline_.error;
  EXPECT_EQ(service.preparing(), 0u);
}

TEST(SpeechBackground, AFailureIsNotRememberedButAPinnedLineIsAnsweredAsSaid) {
  auto moody = std::make_shared<MoodyBackend>();
  const auto owned = serviceWith(moody);
  speech::SpeechService& service = *owned;
  const auto failed = service.prepare(line("Hi"));
  service.waitUntilPrepared();
  EXPECT_EQ(failed->result().line, nullptr);
  // Pinned (a held block being realized): answered as it was said, the backend not asked.
  service.pin({failed});
  EXPECT_EQ(service.speak(line("Hi")).error, failed->result().error);
  EXPECT_EQ(moody->calls, 1);
  service.unpin({failed});
  // Not pinned: a failure is asked again; once the backend learned the line, it is said.
  EXPECT_EQ(service.speak(line("Hi")).line, nullptr);
  EXPECT_EQ(moody->calls, 2);
  moody->knows = true;  // as RecordedSpeech::addLine would
  const speech::SpeechService::Result said = service.speak(line("Hi"));
  EXPECT_NE(said.line, nullptr) << said.error;
  EXPECT_EQ(moody->calls, 3);
}

}  // namespace marionette
