// `marionette retarget SRC --to TARGET -o OUT.glb|OUT.bvh`: a motion made for one
// skeleton, played by another character, written as glTF (the character with the
// animation) or BVH (the animation on the target's skeleton).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "marionette/io/bvh_writer.hpp"
#include "marionette/io/gltf_writer.hpp"
#include "marionette/io/import.hpp"
#include "marionette/retarget/retarget_metrics.hpp"
#include "marionette/retarget/retargeter.hpp"

namespace marionette::cli {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "marionette retarget: error: %s\n", message.c_str());
  return 2;
}

// A joint map: the file given, else the shipped map that fits the asset, else a guess.
// Diagnostics to stderr; which map was taken as a note.
std::optional<retarget::JointMap> jointMapFor(const std::string& file, const Asset& asset, const std::string& what,
                                              const std::vector<std::string>& folders, bool& warned) {
  retarget::JointMapResult r;
  if (!file.empty()) {
    r = retarget::loadJointMap(file, asset);
  } else if (auto match = retarget::findJointMap(asset, folders)) {
    std::fprintf(stderr, "marionette retarget: note: %s: joint map %s (shipped; fits every joint it names)\n",
                 what.c_str(), match->file.c_str());
    r = std::move(match->result);
  } else {
    r = retarget::guessJointMap(asset);
    std::fprintf(stderr, "marionette retarget: note: %s: joint map guessed from names and topology (--%s-map M.json "
                 "to give one)\n", what.c_str(), what.rfind("source", 0) == 0 ? "src" : "dst");
  }
  std::fputs(r.diagnostics.format().c_str(), stderr);
  if (!r.diagnostics.ok()) {
    std::fprintf(stderr, "marionette retarget: error: no usable joint map for the %s\n", what.c_str());
    return std::nullopt;
  }
  warned |= r.diagnostics.hasWarnings();
  return std::move(r.map);
}

}  // namespace

int retargetCommand(const RetargetCommandOptions& a) {
  const bool bvh = endsWith(a.output, ".bvh");

  ImportOptions motionOptions;
  motionOptions.loadMeshes = false;
  ImportResult src = importAsset(a.source, motionOptions);
  std::fputs(src.diagnostics.format().c_str(), stderr);
  if (!src.ok()) return 2;
  ImportOptions characterOptions;
  characterOptions.loadMeshes = !bvh;
  ImportResult dst = importAsset(a.target, characterOptions);
  std::fputs(dst.diagnostics.format().c_str(), stderr);
  if (!dst.ok()) return 2;
  const Asset& source = *src.asset;
  Asset& target = *dst.asset;
  bool warned = src.diagnostics.hasWarnings() || dst.diagnostics.hasWarnings();

  const Clip* clip = nullptr;
  for (const Clip& c : source.clips)
    if (a.clip.empty() || c.name == a.clip) {
      clip = &c;
      break;
    }
  std::string names;
  for (const Clip& c : source.clips) names += (names.empty() ? "" : ", ") + ("'" + c.name + "'");
  if (!clip)
    return fail(a.source + ": " +
                (a.clip.empty() ? "has no animation" : "no clip named '" + a.clip + "' (clips: " + names + ")"));
  if (a.clip.empty() && source.clips.size() > 1)
    std::fprintf(stderr, "marionette retarget: note: no --clip: took '%s', the first of %zu clips (%s)\n",
                 clip->name.c_str(), source.clips.size(), names.c_str());

  const auto sourceMap = jointMapFor(a.sourceMap, source, "source " + a.source, a.jointMapFolders, warned);
  const auto targetMap = jointMapFor(a.targetMap, target, "target " + a.target, a.jointMapFolders, warned);
  if (!sourceMap || !targetMap) return 2;

  retarget::RetargetOptions options;
  options.sourceHipsReference = retarget::standingHipsReference(source.skeleton, *sourceMap, *clip, target.skeleton, *targetMap);
  options.ik.feet = a.feet;
  options.ik.hands = a.hands;
  const auto t0 = std::chrono::steady_clock::now();
  const retarget::Retargeter r =
      retarget::Retargeter::bind(source.skeleton, *sourceMap, target.skeleton, *targetMap, options);
  Clip out = r.retargetClip(*clip, a.fps);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (const std::string& note : r.notes()) std::fprintf(stderr, "marionette retarget: note: %s\n", note.c_str());
  if (!r.valid()) return fail("cannot retarget " + a.source + " onto " + a.target);
  out.name = clip->name.empty() ? "retargeted" : clip->name;

  Diagnostics written;
  if (bvh) {
    written = writeBvh(a.output, target.skeleton, out);
  } else {
    target.clips = {out};
    written = writeGltf(a.output, target, target.clips);
  }
  std::fputs(written.format().c_str(), stderr);
  if (!written.ok()) return 2;
  warned |= written.hasWarnings();

  if (a.report || a.json) {  // --json alone: the same figures, as JSON
    const auto err = retarget::endEffectorError(source.skeleton, *sourceMap, *clip, target.skeleton, *targetMap, out,
                                                r.facingAlignment());
    const auto sk = retarget::compareSkating(source.skeleton, *sourceMap, *clip, target.skeleton, *targetMap, out);
    const auto dir = retarget::segmentDirectionError(source.skeleton, *sourceMap, *clip, target.skeleton, *targetMap, out,
                                                     r.facingAlignment());
    const int frames = static_cast<int>(out.tracks.empty() ? 0 : out.tracks.front().rotation.keyCount());
    if (a.json) {
      nlohmann::ordered_json j;
      j["source"] = a.source;
      j["target"] = a.target;
      j["output"] = a.output;
      j["clip"] = out.name;
      j["duration"] = out.duration;
      j["frames"] = frames;
      j["ik"] = a.feet ? (a.hands ? "feet,hands" : "feet") : (a.hands ? "hands" : "none");
      j["seconds"] = seconds;
      j["endEffectorMean"] = err.mean;
      j["endEffectorMax"] = err.max;
      j["segmentDirectionMeanDegrees"] = dir.meanDegrees;
      j["segmentDirectionP95Degrees"] = dir.p95Degrees;
      j["segmentDirectionMaxDegrees"] = dir.maxDegrees;
      j["sourceSkating"] = sk.source;
      j["targetSkating"] = sk.target;
      j["skatingRatio"] = sk.ratio;
      j["contactFraction"] = sk.contactFraction;
      std::cout << j.dump(2) << '\n';
    } else {
      std::printf("| metric | value |\n|---|---|\n");
      std::printf("| clip | %s (%.2f s, %d frames) |\n", out.name.c_str(), out.duration, frames);
      std::printf("| retarget time | %.1f ms |\n", seconds * 1e3);
      std::printf("| end-effector error, mean | %.2f %% of height |\n", 100.0 * err.mean);
      std::printf("| end-effector error, max | %.2f %% of height |\n", 100.0 * err.max);
      std::printf("| segment directions (spine, neck, arms, legs), mean | %.2f deg |\n", dir.meanDegrees);
      std::printf("| segment directions, p95 | %.2f deg |\n", dir.p95Degrees);
      std::printf("| foot skating in the source's contacts (%.0f %% of foot-frames), source | %.4f leg lengths/s |\n",
                  100.0 * sk.contactFraction, sk.source);
      std::printf("| foot skating in the source's contacts, output | %.4f leg lengths/s |\n", sk.target);
      std::printf("| skating ratio (output / source) | %.3f |\n", sk.ratio);
    }
  }
  return warned ? 1 : 0;
}

}  // namespace marionette::cli
