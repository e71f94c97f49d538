// The C API's recorded voice lines (mn_scene_add_speech_line): a <speech> whose text
// matches a line is said with its recording and phoneme alignment, no synthesizer needed.
// What a library without espeak-ng (libmarionette_c, the web build) says lines with.
#include <memory>
#include <string>

#include "handles.hpp"
#include "marionette/speech/recorded_speech.hpp"

using namespace marionette::capi;

extern "C" {

mn_status mn_scene_add_speech_line(mn_scene* scene, const char* text, const char* audio_path, const char* alignment_path,
                                   mn_read_file_fn read_file, void* read_file_user) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_add_speech_line: scene") + notLive(scene));
  if (!text || !*text) return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_add_speech_line: text is NULL or empty");
  if (!alignment_path || !*alignment_path)
    return fail(scene, MN_ERROR_INVALID_ARGUMENT, "mn_scene_add_speech_line: alignment_path is NULL or empty");
  // inCall: the engine's read function may not destroy the scene under this call.
  return inCall(scene, "mn_scene_add_speech_line", [&] {
    // Added to the speech service with its first line: lines come before any synthesizer.
    auto lines = scene->recordedLines ? scene->recordedLines : std::make_shared<marionette::speech::RecordedSpeech>();
    const std::string error = lines->addLine(text, audio_path && *audio_path ? audio_path : std::filesystem::path(),
                                             alignment_path, engineReader(read_file, read_file_user));
    if (!error.empty()) return fail(scene, MN_ERROR_LOAD, "mn_scene_add_speech_line: " + error);
    if (!scene->recordedLines) {
      scene->recordedLines = lines;
      scene->scene.speech().addBackend(lines);
    } else {
      scene->scene.speech().forgetCachedLines();  // a text said before is said with this line now
    }
    return MN_OK;
  });
}

}  // extern "C"
