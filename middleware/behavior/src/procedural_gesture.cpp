#include "marionette/behavior/procedural_gesture.hpp"

#include "marionette/rig/gesture_vocabulary.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "marionette/animation/pose.hpp"
#include "marionette/core/text.hpp"
#include "marionette/rig/rig.hpp"

namespace marionette {

namespace {

// Where a hand goes, in arm lengths from its shoulder: x out to its own side (mirrored
// for the left hand), y up, z forward. `wave`: a side-to-side swing of that amplitude,
// two cycles per stroke repetition.
struct HandPath {
  glm::vec3 ready, stroke, after;
  float wave = 0.0f;
};
struct Shape {
  std::array<std::string_view, 3> names;  // the lexeme and its other names ("" = none)
  bool left, right;                       // the hands it uses when the request does not say
  HandPath path;
};

// Laid out after the BEAT / deictic / emblem families of McNeill and the SmartBody gesture
// map's names; the places are the hand's, in front of the body, so that hands never cross
// the torso but for ME (to the chest) and NEGATION (a wipe across the front).
constexpr Shape kShapes[] = {
    {{"BEAT", "RHYTHM", ""}, false, true, {{0.25f, -0.55f, 0.45f}, {0.25f, -0.75f, 0.5f}, {0.25f, -0.6f, 0.45f}}},
    {{"CHOP", "EMPHASIS", ""}, false, true, {{0.15f, -0.15f, 0.55f}, {0.15f, -0.65f, 0.6f}, {0.15f, -0.6f, 0.55f}}},
    {{"DEICTIC", "POINT", ""}, false, true, {{0.2f, -0.4f, 0.5f}, {0.15f, -0.1f, 0.95f}, {0.15f, -0.12f, 0.92f}}},
    {{"YOU", "", ""}, false, true, {{0.2f, -0.5f, 0.45f}, {0.12f, -0.25f, 0.9f}, {0.12f, -0.3f, 0.85f}}},
    {{"ME", "SELF", ""}, false, true, {{0.1f, -0.6f, 0.35f}, {-0.45f, -0.35f, 0.28f}, {-0.45f, -0.38f, 0.28f}}},
    {{"WAVE", "GREET", "HELLO"}, false, true, {{0.45f, 0.3f, 0.25f}, {0.45f, 0.38f, 0.25f}, {0.45f, 0.35f, 0.25f}, 0.15f}},
    {{"SHRUG", "", ""}, true, true, {{0.35f, -0.65f, 0.35f}, {0.5f, -0.55f, 0.45f}, {0.48f, -0.57f, 0.43f}}},
    {{"QUESTION", "OFFER", ""}, false, true, {{0.3f, -0.65f, 0.35f}, {0.4f, -0.5f, 0.55f}, {0.4f, -0.52f, 0.53f}}},
    {{"CONTRAST", "", ""}, true, true, {{0.2f, -0.55f, 0.5f}, {0.55f, -0.5f, 0.4f}, {0.53f, -0.52f, 0.4f}}},
    {{"NEGATION", "NO", ""}, false, true, {{-0.1f, -0.4f, 0.55f}, {0.55f, -0.4f, 0.5f}, {0.53f, -0.42f, 0.48f}}},
    {{"SWEEP", "INCLUSIVITY", ""}, true, true, {{0.05f, -0.45f, 0.6f}, {0.6f, -0.45f, 0.4f}, {0.58f, -0.47f, 0.4f}}},
    {{"LEFT", "", ""}, true, false, {{0.25f, -0.5f, 0.4f}, {0.7f, -0.3f, 0.35f}, {0.68f, -0.32f, 0.35f}}},
    {{"RIGHT", "", ""}, false, true, {{0.25f, -0.5f, 0.4f}, {0.7f, -0.3f, 0.35f}, {0.68f, -0.32f, 0.35f}}},
};

const std::vector<std::string_view>& lexemeList() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const Shape& shape : kShapes)
      for (std::string_view name : shape.names)
        if (!name.empty()) v.push_back(name);
    return v;
  }();
  return names;
}

int shapeOf(std::string_view lexeme) noexcept {
  for (std::size_t i = 0; i < std::size(kShapes); ++i)
    for (std::string_view name : kShapes[i].names)
      if (!name.empty() && equalsIgnoringCase(name, lexeme)) return static_cast<int>(i);
  return -1;
}

float ease(double u) noexcept {  // smoothstep on [0, 1]
  const double c = std::clamp(u, 0.0, 1.0);
  return static_cast<float>(c * c * (3.0 - 2.0 * c));
}

// The hand's place in the character's frame (arm lengths) at `clock`.
glm::vec3 placeAt(const GestureState& st, double clock) noexcept {
  const HandPath& p = kShapes[static_cast<std::size_t>(st.shape)].path;
  glm::vec3 at = p.ready;
  double previousEnd = -1.0;
  for (const GestureState::Stroke& k : st.strokes) {
    if (clock < k.start) {  // before this repetition: back from the last one's end to ready
      if (previousEnd >= 0.0 && k.start > previousEnd)
        at = glm::mix(p.after, p.ready, ease((clock - previousEnd) / (k.start - previousEnd)));
      return at;
    }
    if (clock < k.end) {
      at = clock < k.peak ? glm::mix(p.ready, p.stroke, ease(k.peak > k.start ? (clock - k.start) / (k.peak - k.start) : 1.0))
                          : glm::mix(p.stroke, p.after, ease(k.end > k.peak ? (clock - k.peak) / (k.end - k.peak) : 1.0));
      if (p.wave != 0.0f && k.end > k.start)
        at.x += p.wave * static_cast<float>(std::sin(4.0 * 3.14159265358979 * (clock - k.start) / (k.end - k.start)));
      return at;
    }
    at = p.after;
    previousEnd = k.end;
  }
  return at;
}

}  // namespace

std::span<const std::string_view> proceduralGestureLexemes() noexcept { return lexemeList(); }

bool hasProceduralGesture(std::string_view lexeme) noexcept { return shapeOf(lexeme) >= 0; }

std::string bindProceduralGesture(const BehaviorRequest& request, const Rig& rig, const Skeleton& skeleton,
                                  GestureState& st, std::string& warning) {
  const GestureParameters* p = request.as<GestureParameters>();
  const std::string lexeme = p ? p->lexeme : std::string();
  st.shape = shapeOf(lexeme);
  if (st.shape < 0 && !lexeme.empty()) {
    // Another realizer's name (Greta's greet_*, SmartBody's METAPHORIC, ...): the profile's
    // vocabulary, then the shipped one (rig/gesture_vocabulary.hpp), played as what it maps to.
    const char* from = "the profile's gestureVocabulary";
    const GestureVocabularyEntry* m = matchGestureVocabulary(lexeme, rig.profile().gestureVocabulary);
    if (!m || shapeOf(m->lexeme) < 0) {
      m = matchGestureVocabulary(lexeme, defaultGestureVocabulary());
      from = "assets/gestures/vocabulary.json";
    }
    if (m && shapeOf(m->lexeme) >= 0) {
      st.shape = shapeOf(m->lexeme);
      warning += std::string(warning.empty() ? "" : "; ") + "gesture '" + lexeme.substr(0, 40) + "' is played as the procedural " +
                 m->lexeme + " (" + from + ": '" + m->pattern + "')";
    }
  }
  if (st.shape < 0) {
    std::string known;
    for (std::string_view name : proceduralGestureLexemes()) known += (known.empty() ? "" : ", ") + std::string(name);
    return lexeme.empty() ? "a gesture needs a lexeme (procedural ones: " + known + ") or a clip"
                          : "gesture lexeme '" + lexeme.substr(0, 40) +
                                "' names no clip of the character and no procedural gesture (" + known + ")";
  }
  const RigJoints& j = rig.joints();
  st.limb[0] = makeLimbIk(skeleton, limbWithEnd(j.leftArm, skeleton));
  st.limb[1] = makeLimbIk(skeleton, limbWithEnd(j.rightArm, skeleton));
  for (int side = 0; side < 2; ++side) {
    const LimbIk& l = st.limb[side];
    if (l.upper < 0) continue;
    const std::span<const Transform> rest = skeleton.restPose;
    const glm::vec3 shoulder(modelMatrixOf(skeleton, rest, l.upper)[3]), elbow(modelMatrixOf(skeleton, rest, l.lower)[3]);
    st.armLength[side] = glm::length(elbow - shoulder) + glm::length(limbEndModel(skeleton, rest, l) - elbow);
  }
  if (st.limb[0].upper < 0 && st.limb[1].upper < 0)
    return "the character has no arm to gesture with (set leftArm / rightArm in its profile or joint map)";
  const Shape& shape = kShapes[static_cast<std::size_t>(st.shape)];
  const PointingArms hands = p->hands;
  const bool want[2] = {hands == PointingArms::Nearest ? shape.left : hands == PointingArms::Left || hands == PointingArms::Both,
                        hands == PointingArms::Nearest ? shape.right : hands == PointingArms::Right || hands == PointingArms::Both};
  for (int side = 0; side < 2; ++side) {
    if (!want[side]) continue;
    if (st.limb[side].upper >= 0 && st.armLength[side] > 1e-4f) st.arm[side] = true;
    else warning += std::string(warning.empty() ? "" : "; ") + "the character has no usable " + (side ? "right" : "left") + " arm";
  }
  if (!st.arm[0] && !st.arm[1]) {  // the one hand it has does it
    const int other = want[0] ? 1 : 0;
    if (st.limb[other].upper >= 0 && st.armLength[other] > 1e-4f) st.arm[other] = true;
    else return "the character has no usable arm for gesture '" + lexeme + "'";
  }
  st.left = glm::length(j.leftAxis) > 1e-6f ? glm::normalize(j.leftAxis) : glm::vec3(1.0f, 0.0f, 0.0f);
  // The phases from the request's sync points (repetitions carry ":N").
  double ready = request.start(), relax = request.end();  // the weight envelope's: only a stroke-less request needs them
  st.strokes.clear();
  for (const BehaviorSync& s : request.syncs) {
    const std::string_view name = s.name;
    const std::string_view base = name.substr(0, name.find(':'));
    if (base == "ready") ready = s.time;
    else if (base == "relax") relax = s.time;
    else if (base == "strokeStart") st.strokes.push_back({s.time, s.time, s.time});
    else if (base == "stroke" && !st.strokes.empty()) st.strokes.back().peak = st.strokes.back().end = s.time;
    else if (base == "strokeEnd" && !st.strokes.empty()) st.strokes.back().end = s.time;
  }
  if (st.strokes.empty()) {  // a request without stroke sync points: the middle of its time
    const double mid = 0.5 * (ready + relax);
    st.strokes.push_back({ready, mid, relax});
  }
  return {};
}

glm::vec3 proceduralGestureHand(const GestureState& st, int side, double clock, const glm::vec3& shoulder) noexcept {
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const glm::vec3 forward = glm::cross(st.left, up);
  const glm::vec3 out = side == 0 ? st.left : -st.left;
  const glm::vec3 place = placeAt(st, clock);
  return shoulder + st.armLength[side] * (place.x * out + place.y * up + place.z * forward);
}

void updateProceduralGesture(const GestureState& st, double clock, float weight, const Skeleton& skeleton,
                             std::span<Transform> pose) noexcept {
  if (st.shape < 0 || !(weight > 0.0f)) return;
  const float w = std::min(weight, 1.0f);
  const glm::vec3 up(0.0f, 1.0f, 0.0f);
  const glm::vec3 forward = glm::cross(st.left, up);
  for (int side = 0; side < 2; ++side) {
    if (!st.arm[side]) continue;
    const LimbIk& limb = st.limb[side];
    const glm::vec3 shoulder(modelMatrixOf(skeleton, pose, limb.upper)[3]);
    const glm::vec3 hand = proceduralGestureHand(st, side, clock, shoulder);
    const glm::vec3 out = side == 0 ? st.left : -st.left;
    const glm::vec3 pole = shoulder + st.armLength[side] * (0.5f * out - 0.7f * up - 0.5f * forward);  // elbow out, down, back
    (void)solveTwoBoneIk(skeleton, pose, limb, hand, pole, w);
  }
}

}  // namespace marionette
