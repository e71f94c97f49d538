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

constexpr const char* kUsage =
    "usage: marionette retarget SRC_MOTION --to TARGET_CHARACTER [--src-map M.json] [--dst-map M.json]\n"
    "                           [--clip NAME] [--fps F] [--ik feet,hands|none] -o OUT.glb|OUT.gltf|OUT.bvh\n"
    "                           [--report] [--json]\n";

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

struct Args {
  std::string source, target, sourceMap, targetMap, clip, output;
  float fps = 0.0f;
  bool feet = false, hands = false, report = false, json = false;
};

int fail(const std::string& message) {
  std::fprintf(stderr, "marionette retarget: error: %s\n", message.c_str());
  return 2;
}

// Returns an exit code >= 0 on a usage error, -1 when the arguments are fine.
int parse(const std::vector<std::string>& args, Args& a) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& s = args[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= args.size()) return false;
      out = args[++i];
      return true;
    };
    std::string v;
    if (s == "--to" || s == "--src-map" || s == "--dst-map" || s == "--clip" || s == "-o" || s == "--fps" ||
        s == "--ik") {
      if (!value(v)) return fail("option '" + s + "' needs a value");
      if (s == "--to") a.target = v;
      else if (s == "--src-map") a.sourceMap = v;
      else if (s == "--dst-map") a.targetMap = v;
      else if (s == "--clip") a.clip = v;
      else if (s == "-o") a.output = v;
      else if (s == "--fps") {
        char* end = nullptr;
        a.fps = std::strtof(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(a.fps > 0.0f) || a.fps > 1000.0f)
          return fail("--fps '" + v + "': expected frames per second in (0, 1000]");
      } else {  // --ik
        std::size_t start = 0;
        while (start <= v.size()) {
          const std::size_t comma = v.find(',', start);
          const std::string part = v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
          if (part == "feet") a.feet = true;
          else if (part == "hands") a.hands = true;
          else if (part != "none") return fail("--ik '" + v + "': expected feet, hands, feet,hands or none");
          if (comma == std::string::npos) break;
          start = comma + 1;
        }
      }
    } else if (s == "--report") {
      a.report = true;
    } else if (s == "--json") {
      a.json = true;
    } else if (!s.empty() && s[0] == '-') {
      return fail("unknown option '" + s + "'");
    } else if (a.source.empty()) {
      a.source = s;
    } else {
      return fail("one source motion expected, got '" + s + "' too");
    }
  }
  if (a.source.empty() || a.target.empty() || a.output.empty()) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  if (!endsWith(a.output, ".glb") && !endsWith(a.output, ".gltf") && !endsWith(a.output, ".bvh"))
    return fail("output '" + a.output + "': expected a .glb, .gltf or .bvh file name");
  return -1;
}

// A joint map from a file, or guessed from the asset; diagnostics to stderr.
std::optional<retarget::JointMap> jointMapFor(const std::string& file, const Asset& asset, const std::string& what,
                                              bool& warned) {
  retarget::JointMapResult r = file.empty() ? retarget::guessJointMap(asset) : retarget::loadJointMap(file, asset);
  std::fputs(r.diagnostics.format().c_str(), stderr);
  if (!r.diagnostics.ok()) {
    std::fprintf(stderr, "marionette retarget: error: no usable joint map for the %s\n", what.c_str());
    return std::nullopt;
  }
  warned |= r.diagnostics.hasWarnings();
  return std::move(r.map);
}

}  // namespace

int retargetCommand(const std::vector<std::string>& args) {
  Args a;
  if (const int code = parse(args, a); code >= 0) return code;
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
  if (!clip) {
    std::string names;
    for (const Clip& c : source.clips) names += (names.empty() ? "" : ", ") + ("'" + c.name + "'");
    return fail(a.source + ": " +
                (a.clip.empty() ? "has no animation" : "no clip named '" + a.clip + "' (clips: " + names + ")"));
  }

  const auto sourceMap = jointMapFor(a.sourceMap, source, "source " + a.source, warned);
  const auto targetMap = jointMapFor(a.targetMap, target, "target " + a.target, warned);
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

  if (a.report) {
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
