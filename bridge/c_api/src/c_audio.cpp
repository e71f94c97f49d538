// The C API's sounds (<bmlt:audiofile>): mn_scene_set_audio_callback, mn_scene_set_audio_files
// and the forwarder's onAudio / onAudioStopped (docs/bridge.md).
#include <string>

#include "handles.hpp"

using namespace marionette::capi;

void CallbackForwarder::onAudio(const marionette::Character& character, std::string_view behaviorId,
                                const marionette::speech::AudioClip& clip, std::string_view file, double sceneStart) {
  if (!owner_.audioFn) return;
  text2_.assign(behaviorId);
  text3_.assign(file);
  const mn_audio a{MN_AUDIO_PLAY,    character.name().c_str(), text2_.c_str(), clip.samples.data(),
                   clip.frames(),    clip.channels,            clip.sampleRate, text3_.c_str(),
                   sceneStart,       clip.duration()};
  owner_.audioFn(owner_.audioUser, &a);
}

void CallbackForwarder::onAudioStopped(const marionette::Character& character, std::string_view behaviorId, double time) {
  if (!owner_.audioFn) return;
  text2_.assign(behaviorId);
  const mn_audio a{MN_AUDIO_STOP, character.name().c_str(), text2_.c_str(), nullptr, 0, 0, 0, "", time, 0.0};
  owner_.audioFn(owner_.audioUser, &a);
}

extern "C" {

mn_status mn_scene_set_audio_callback(mn_scene* scene, mn_audio_fn fn, void* user) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_audio_callback: scene") + notLive(scene));
  scene->audioFn = fn;
  scene->audioUser = user;
  return MN_OK;
}

mn_status mn_scene_set_audio_files(mn_scene* scene, const char* directory, mn_read_file_fn read_file,
                                   void* read_file_user) {
  if (!isLive(scene))
    return fail(nullptr, MN_ERROR_INVALID_ARGUMENT, std::string("mn_scene_set_audio_files: scene") + notLive(scene));
#ifdef MARIONETTE_C_HAS_BML
  return guarded(scene, [&] {
    scene->realizer->setFiles(engineReader(read_file, read_file_user), directory ? directory : "");
    return MN_OK;
  });
#else
  (void)directory, (void)read_file, (void)read_file_user;
  return fail(scene, MN_ERROR_UNSUPPORTED, "mn_scene_set_audio_files: this library was built without BML (MARIONETTE_WITH_BML=OFF)");
#endif
}

}  // extern "C"
