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
#include "marionette/retarget/target_check.hpp"

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

// "all 5 effectors" or "2 of 5 effectors: leftFoot, rightFoot; not leftHand, rightHand, head".
std::string coverage(const std::vector<std::string>& measured, const std::vector<std::string>& missing,
                     const std::string& noun) {
  const std::size_t total = measured.size() + missing.size();
  if (missing.empty()) return "all " + std::to_string(total) + " " + noun;
  auto list = [](const std::vector<std::string>& v) {
    std::string out;
    for (const std::string& x : v) out += (out.empty() ? "" : ", ") + x;
    return out;
  };
  return std::to_string(measured.size()) + " of " + std::to_string(total) + " " + noun + ": " +
         (measured.empty() ? "" : list(measured) + "; ") + "not " + list(missing);
}

std::vector<std::string> boneNames(const std::vector<retarget::Bone>& bones) {
  std::vector<std::string> out;
  for (retarget::Bone b : bones) out.emplace_back(retarget::boneName(b));
  return out;
}

// A figure, or "n/a" where it is over nothing.
std::string figure(bool measured, const char* format, double value) {
  if (!measured) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// A character that is not a full humanoid: refused (exit 2, no file), or with --allow-partial
// retargeted as far as it maps, with a warning. Nothing is done for one without a skeleton.
bool acceptable(const retarget::TargetCheck& check, const std::string& what, const std::string& file,
                bool allowPartial, bool& warned) {
  if (check.kind == retarget::TargetClass::Humanoid) return true;
  if (check.kind == retarget::TargetClass::NoSkeleton || !allowPartial) {
    std::fprintf(stderr, "marionette retarget: error: %s %s: %s%s\n", what.c_str(), file.c_str(), check.reason.c_str(),
                 check.kind == retarget::TargetClass::NoSkeleton
                     ? ""
                     : " (--allow-partial retargets what maps, and the report says what it covers)");
    return false;
  }
  std::fprintf(stderr, "marionette retarget: warning: %s %s: %s; --allow-partial: only what maps is retargeted\n",
               what.c_str(), file.c_str(), check.reason.c_str());
  warned = true;
  return true;
}

}  // namespace

int retargetCommand(const RetargetCommandOptions& a) {
  const bool bvh = endsWith(a.output, ".bvh");

  ImportOptions motionOptions;
  motionOptions.loadMeshes = false;
  motionOptions.isolateThirdPartyParsers = true;  // a tool: Assimp's readers run in a child first
  ImportResult src = importAsset(a.source, motionOptions);
  std::fputs(src.diagnostics.format().c_str(), stderr);
  if (!src.ok()) return 2;
  ImportOptions characterOptions;
  characterOptions.loadMeshes = !bvh;
  characterOptions.isolateThirdPartyParsers = true;
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
  // Before anything is written: a target (or source) that is not a humanoid is refused.
  const retarget::TargetCheck sourceCheck = retarget::checkRetargetTarget(source, *sourceMap, false);
  const retarget::TargetCheck targetCheck = retarget::checkRetargetTarget(target, *targetMap, !bvh);
  if (!acceptable(sourceCheck, "source", a.source, a.allowPartial, warned) ||
      !acceptable(targetCheck, "target", a.target, a.allowPartial, warned))
    return 2;

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
    const bool effectors = err.samples > 0, segments = dir.samples > 0, skating = sk.contacts > 0;
    const std::vector<std::string> effectorNames = boneNames(err.effectors), missingEffectors = boneNames(err.missing);
    if (a.json) {
      nlohmann::ordered_json j;
      j["source"] = a.source;
      j["target"] = a.target;
      j["output"] = a.output;
      j["targetClass"] = std::string(retarget::targetClassName(targetCheck.kind));
      j["clip"] = out.name;
      j["duration"] = out.duration;
      j["frames"] = frames;
      j["ik"] = a.feet ? (a.hands ? "feet,hands" : "feet") : (a.hands ? "hands" : "none");
      j["seconds"] = seconds;
      // Over nothing: null, never 0.
      auto value = [](bool measured, double v) { return measured ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
      j["endEffectors"] = effectorNames;
      j["endEffectorsMissing"] = missingEffectors;
      j["endEffectorMean"] = value(effectors, err.mean);
      j["endEffectorMax"] = value(effectors, err.max);
      j["segments"] = dir.segments;
      j["segmentsMissing"] = dir.missing;
      j["segmentDirectionMeanDegrees"] = value(segments, dir.meanDegrees);
      j["segmentDirectionP95Degrees"] = value(segments, dir.p95Degrees);
      j["segmentDirectionMaxDegrees"] = value(segments, dir.maxDegrees);
      j["skatingFeet"] = sk.feet;
      j["sourceSkating"] = value(skating, sk.source);
      j["targetSkating"] = value(skating, sk.target);
      j["skatingRatio"] = value(skating && sk.source > 0.0, sk.ratio);
      j["contactFraction"] = value(skating, sk.contactFraction);
      std::cout << j.dump(2) << '\n';
    } else {
      const std::string effectorCover = coverage(effectorNames, missingEffectors, "effectors");
      const std::string segmentCover = coverage(dir.segments, dir.missing, "segments");
      std::printf("| metric | value |\n|---|---|\n");
      std::printf("| target | %s |\n", std::string(retarget::targetClassName(targetCheck.kind)).c_str());
      std::printf("| clip | %s (%.2f s, %d frames) |\n", out.name.c_str(), out.duration, frames);
      std::printf("| retarget time | %.1f ms |\n", seconds * 1e3);
      std::printf("| end-effector error (%s), mean | %s |\n", effectorCover.c_str(),
                  figure(effectors, "%.2f %% of height", 100.0 * err.mean).c_str());
      std::printf("| end-effector error, max | %s |\n", figure(effectors, "%.2f %% of height", 100.0 * err.max).c_str());
      std::printf("| segment directions (%s), mean | %s |\n", segmentCover.c_str(),
                  figure(segments, "%.2f deg", dir.meanDegrees).c_str());
      std::printf("| segment directions, p95 | %s |\n", figure(segments, "%.2f deg", dir.p95Degrees).c_str());
      std::printf("| foot skating (%d of 2 feet) in the source's contacts (%s of foot-frames), source | %s |\n",
                  sk.feet, figure(skating, "%.0f %%", 100.0 * sk.contactFraction).c_str(),
                  figure(skating, "%.4f leg lengths/s", sk.source).c_str());
      std::printf("| foot skating in the source's contacts, output | %s |\n",
                  figure(skating, "%.4f leg lengths/s", sk.target).c_str());
      std::printf("| skating ratio (output / source) | %s |\n", figure(skating && sk.source > 0.0, "%.3f", sk.ratio).c_str());
    }
  }
  return warned ? 1 : 0;
}

}  // namespace marionette::cli
