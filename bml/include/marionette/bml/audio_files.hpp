// AsapRealizer's <bmlt:audiofile id fileName start end> (namespace kBmltNamespace): a WAV
// played from the behavior's start, its length the behavior's default duration. An end
// the block gives cuts the sound there (the engine is told: SceneListener::onAudioStopped),
// or, past the sound's end, leaves silence until it. The realizer reads each file when it
// realizes the block (command time, once) and hands the decoded clip over with the
// behavior's request (AudioParameters); no body channel is used.
#pragma once
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "marionette/bml/document.hpp"
#include "marionette/core/file_reader.hpp"
#include "marionette/speech/audio_clip.hpp"

namespace marionette::bml {

// Where fileName is read: relative names in `directory` ("" = the working directory),
// through `reader` (core/file_reader.hpp; empty: the disk).
struct AudioFileAccess {
  FileReader reader{};
  std::string directory{};
};

struct LoadedAudio {
  std::string behaviorId;
  std::shared_ptr<const speech::AudioClip> clip;
  std::string file;  // as resolved
};

// The path fileName names: absolute as given, else in `directory`; '/'-separated, "." and
// ".." folded (as FileReader expects).
[[nodiscard]] std::string resolveAudioFile(std::string_view fileName, std::string_view directory);

// Reads the WAV of every <bmlt:audiofile> of `block`. One that cannot be played (no fileName;
// a file missing, unreadable, malformed, or without samples) is removed from the block with
// a CANNOT_CREATE_BEHAVIOR warning in `warnings` naming the block, the behavior, the file and
// the problem (fatal when the behavior is required: the block fails); the scheduler then
// removes the behaviors that refer to it (NO_SUCH_TARGET), as BML 1.0 has it.
[[nodiscard]] std::vector<LoadedAudio> loadAudioFiles(Block& block, const AudioFileAccess& access,
                                                      std::vector<Warning>& warnings);

}  // namespace marionette::bml
