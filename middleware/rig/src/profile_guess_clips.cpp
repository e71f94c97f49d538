// The clips of a character profile: idle, walk and run cycles and arm gestures,
// from clip names.
#include "profile_guess.hpp"

#include <algorithm>
#include <initializer_list>
#include <utility>

namespace marionette::profile_detail {

namespace {

// Clip-name padding of exporters and libraries ("Armature|mixamo.com|Layer0", "Walk_Loop").
const std::set<std::string_view> kClipNoise = {"anim",     "animation", "action", "armature", "clip",    "take",
                                               "loop",     "looped",    "cycle",  "inplace",  "in",      "place",
                                               "default",  "mixamo",    "com",    "layer",    "character", "fwd",
                                               "forward",  "rig",       "root",   "motion"};

// Words that make a clip something other than the plain cycle ("WalkJump", "Idle_to_Walk").
const std::set<std::string_view> kClipExclusions = {"jump",  "to",     "start", "stop",  "end",    "turn",
                                                    "transition", "back", "backward", "backwards", "strafe",
                                                    "crouch", "injured", "sit", "sitting", "death", "die",
                                                    "attack", "left", "right", "l", "r"};

std::vector<std::string> clipCore(const std::string& name) {
  // Blender exports "Armature|Idle": the action name is the last part.
  const auto bar = name.find_last_of('|');
  std::vector<std::string> core;
  for (auto& w : words(bar == std::string::npos ? std::string_view(name) : std::string_view(name).substr(bar + 1)))
    if (!isDigit(w[0]) && !kClipNoise.count(w)) core.push_back(std::move(w));
  return core;
}

// The clip best named like one of `ws` (earlier words first; a bare word beats a
// qualified one like "Slow Run"); "" when none.
std::string findClip(const Asset& asset, std::initializer_list<std::string_view> ws) {
  int bestScore = 1 << 30;
  std::string best;
  for (const Clip& clip : asset.clips) {
    const auto core = clipCore(clip.name);
    if (core.empty() || core.size() > 2) continue;
    if (std::any_of(core.begin(), core.end(), [](const std::string& w) { return kClipExclusions.count(w) > 0; })) continue;
    int rank = 0;
    for (std::string_view w : ws) {
      if (std::find(core.begin(), core.end(), w) != core.end()) {
        const int score = rank * 2 + (core.size() == 1 ? 0 : 1);
        if (score < bestScore) bestScore = score, best = clip.name;
        break;
      }
      ++rank;
    }
  }
  return best;
}

// Gesture lexemes and the joined clip-name words that perform them. Only arm and
// hand gestures: head nods and shakes ("Yes", "No") are head behaviors in BML.
const std::vector<std::pair<const char*, std::vector<std::string_view>>> kGestureRules = {
    {"WAVE", {"wave", "waving", "wavehand", "handwave"}},
    {"THUMBS_UP", {"thumbsup", "thumbup"}},
    {"POINT", {"point", "pointing"}},
    {"CLAP", {"clap", "clapping"}},
    {"SHRUG", {"shrug", "shrugging"}},
    {"CROSS_ARMS", {"crossarms", "armscrossed", "crossedarms"}},
};

}  // namespace

void guessClips(const Asset& asset, CharacterProfile& p, Notes& notes) {
  auto note = [&](const char* field, const std::string& clip) {
    notes.emplace_back(field, std::string(field) + ": " + (clip.empty() ? "none" : inQuotes(clip) + " (name)"));
  };
  p.idle = findClip(asset, {"idle", "idling", "breathing", "stand", "standing"});
  note("idle", p.idle);
  p.walk = findClip(asset, {"walk", "walking"});
  note("walk", p.walk);
  p.run = findClip(asset, {"run", "running", "jog", "jogging", "sprint", "sprinting"});
  note("run", p.run);
  for (const auto& [lexeme, keys] : kGestureRules) {
    for (const Clip& clip : asset.clips) {
      std::string key;
      for (const auto& w : clipCore(clip.name)) key += w;
      if (std::find(keys.begin(), keys.end(), key) == keys.end()) continue;
      p.gestures[lexeme] = clip.name;
      notes.emplace_back("gestures", std::string("gesture ") + lexeme + ": " + inQuotes(clip.name) + " (name)");
      break;
    }
  }
  if (p.gestures.empty()) notes.emplace_back("gestures", "gestures: none");
}

}  // namespace marionette::profile_detail
