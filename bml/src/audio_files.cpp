// <bmlt:audiofile>: resolving fileName and reading its WAV when a block is realized.
#include "marionette/bml/audio_files.hpp"

#include <algorithm>
#include <filesystem>

namespace marionette::bml {

std::string resolveAudioFile(std::string_view fileName, std::string_view directory) {
  const std::filesystem::path name{std::string(fileName)};
  if (name.is_absolute() || directory.empty()) return name.lexically_normal().generic_string();
  return (std::filesystem::path(std::string(directory)) / name).lexically_normal().generic_string();
}

std::vector<LoadedAudio> loadAudioFiles(Block& block, const AudioFileAccess& access, std::vector<Warning>& warnings) {
  std::vector<LoadedAudio> loaded;
  auto failed = [&](const Behavior& b, const std::string& problem) {
    Warning w{WarningType::CannotCreateBehavior, block.id, b.id, b.line, b.column,
              "<bmlt:audiofile> '" + b.id + "' of block '" + block.id + "': " + problem + "; the behavior was removed",
              b.required};
    if (b.required) w.message += " and, being required, made the block fail";
    warnings.push_back(std::move(w));
    return true;
  };
  std::erase_if(block.behaviors, [&](const Behavior& b) {
    if (b.type != "audiofile") return false;
    const Attribute* name = b.attribute("fileName");
    if (!name || name->value.empty()) return failed(b, "it has no fileName (the WAV to play)");
    const std::string file = resolveAudioFile(name->value, access.directory);
    auto clip = std::make_shared<speech::AudioClip>();
    // The reader's message starts with the file: "FILE: cannot read the WAV file (...)", "FILE: truncated ...".
    if (std::string why = speech::readAudioClip(access.reader, file, *clip); !why.empty()) return failed(b, why);
    loaded.push_back({b.id, std::move(clip), file});
    return false;
  });
  return loaded;
}

}  // namespace marionette::bml
