#include "marionette/behavior/procedural_controllers.hpp"

#include "marionette/core/text.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>

namespace marionette {

namespace {
// BML amount: a number in [lo, hi]; anything else is replaced by the default, with a note.
float amountOf(const BehaviorRequest& r, float fallback, float lo, float hi, std::string& warning) {
  const std::string_view text = r.parameter("amount");
  if (text.empty()) return fallback;
  float v = 0.0f;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v) || v < lo || v > hi) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "amount '%.40s' is not a number in [%g, %g]; %g is used", std::string(text).c_str(),
                  static_cast<double>(lo), static_cast<double>(hi), static_cast<double>(fallback));
    warning = buf;
    return fallback;
  }
  return v;
}

// Stroke phases from sync names: strokeStart/stroke/strokeEnd, then ":2", ":3", ...
std::vector<HeadStroke> strokesOf(const BehaviorRequest& r) {
  std::vector<HeadStroke> out;
  for (int n = 1;; ++n) {
    const std::string suffix = n == 1 ? "" : ":" + std::to_string(n);
    const auto a = r.time("strokeStart" + suffix), b = r.time("stroke" + suffix), c = r.time("strokeEnd" + suffix);
    if (!a || !b || !c) break;
    out.push_back({*a, *b, *c});
  }
  if (out.empty()) {  // a request made without BML sync names: BML's default proportions
    const double s = r.start(), d = r.end() - r.start();
    out.push_back({s + 0.2 * d, s + 0.3 * d, s + 0.5 * d});
  }
  return out;
}

std::string knownExpressions(const RigJoints& joints) {
  if (joints.face.empty()) return "its profile maps no expression to morphs";
  std::string list = "its profile maps";
  int n = 0;
  for (const auto& [name, morphs] : joints.face) {
    if (n++ == 8) {
      list += ", ...";
      break;
    }
    list += (n == 1 ? " " : ", ") + name;
  }
  return list;
}
}  // namespace

std::string bindHead(BehaviorTimeline::Entry& e, const Rig& rig, std::string& warning) {
  const BehaviorRequest& r = e.request;
  const std::string_view lexeme = r.parameter("lexeme");
  const auto head = headLexemeFromName(lexeme);
  if (!head)
    return lexeme.empty() ? "a head behavior needs a lexeme (NOD, SHAKE or TILT)"
                          : "head lexeme '" + std::string(lexeme) + "' is not NOD, SHAKE or TILT";
  if (rig.joints().head < 0 && rig.joints().neck < 0)
    return "the character has no head or neck joint (set \"head\" in its profile)";
  HeadMotionState h;
  h.lexeme = *head;
  h.amount = amountOf(r, 0.5f, -1.0f, 1.0f, warning);
  h.strokes = strokesOf(r);
  e.controller = std::move(h);
  return {};
}

std::string bindFace(BehaviorTimeline::Entry& e, const Rig& rig, std::string& warning) {
  const BehaviorRequest& r = e.request;
  std::string expression;
  if (r.kind == BehaviorKind::FaceFacs) {
    const std::string_view au = r.parameter("au");
    if (au.empty()) return "a faceFacs behavior needs an au (a FACS action unit number)";
    expression = "AU" + std::string(au);
  } else {
    expression = toUpper(r.parameter("lexeme"));
    if (expression.empty()) return "a face behavior needs a lexeme";
  }
  const auto it = rig.joints().face.find(expression);
  if (it == rig.joints().face.end())
    return "the character has no morphs for face expression '" + expression + "' (" + knownExpressions(rig.joints()) + ")";
  FaceExpressionState f;
  f.morphs = it->second;
  f.amount = amountOf(r, 1.0f, 0.0f, 1.0f, warning);
  e.controller = std::move(f);
  return {};
}

void applyHead(const HeadMotionState& h, float weight, double t, const Rig& rig, std::span<Transform> pose) noexcept {
  const float shape = headShape(h.lexeme, h.strokes, t);
  if (shape == 0.0f) return;
  const float angle = weight * h.amount * headPeakAngle(h.lexeme) * shape;
  const glm::vec3 axis = headAxis(h.lexeme);
  const RigJoints& j = rig.joints();
  // The neck takes 40 % and the head the rest, in the model frame, so the total is the angle.
  if (j.neck >= 0 && j.head >= 0) {
    rotateInModelFrame(rig.skeleton(), pose, j.neck, glm::angleAxis(0.4f * angle, axis));
    rotateInModelFrame(rig.skeleton(), pose, j.head, glm::angleAxis(0.6f * angle, axis));
  } else {
    rotateInModelFrame(rig.skeleton(), pose, j.head >= 0 ? j.head : j.neck, glm::angleAxis(angle, axis));
  }
}

void applyFace(const FaceExpressionState& f, float weight, std::span<float> morphWeights) noexcept {
  // Expressions add up, each morph clamped to [0, 1].
  for (const auto& [morph, amount] : f.morphs)
    if (morph >= 0 && static_cast<std::size_t>(morph) < morphWeights.size()) {
      float& w = morphWeights[static_cast<std::size_t>(morph)];
      w = std::clamp(w + weight * f.amount * amount, 0.0f, 1.0f);
    }
}

namespace {
float degreesParameter(const BehaviorRequest& r, std::string_view name, std::string& warning) {
  const std::string_view text = r.parameter(name);
  if (text.empty()) return 0.0f;
  float v = 0.0f;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v) || std::fabs(v) > 180.0f) {
    warning = std::string(name) + " '" + std::string(text).substr(0, 40) + "' is not an angle in degrees (-180 to 180); 0 is used";
    return 0.0f;
  }
  return glm::radians(v);
}
}  // namespace

std::string bindGaze(BehaviorTimeline::Entry& e, const Rig& rig,
                     const TargetJointFinder& findJoint, std::string& warning) {
  const BehaviorRequest& r = e.request;
  GazeState g;
  const RigJoints& j = rig.joints();
  if (j.head < 0 && j.neck < 0 && j.leftEye < 0 && j.rightEye < 0)
    return "the character has no eye, head or neck joint to gaze with (set them in its profile)";
  if (std::string why = parseSpatialTarget(r.parameter("target"), "gaze", findJoint, g.target); !why.empty()) return why;
  const std::string_view influence = r.parameter("influence");
  if (!influence.empty()) {
    if (auto i = gazeInfluenceFromName(influence)) g.influence = *i;
    else warning = "influence '" + std::string(influence).substr(0, 40) +
                   "' is not EYES, HEAD, NECK, SHOULDER, WAIST or WHOLE; NECK is used";
  }
  const float offset = degreesParameter(r, "offsetAngle", warning);
  const std::string direction = toUpper(r.parameter("offsetDirection"));
  const float diagonal = 0.70710678f * offset;
  if (direction == "RIGHT") g.offsetYaw = -offset;
  else if (direction == "LEFT") g.offsetYaw = offset;
  else if (direction == "UP") g.offsetPitch = -offset;
  else if (direction == "DOWN") g.offsetPitch = offset;
  else if (direction == "UPRIGHT") g.offsetYaw = -diagonal, g.offsetPitch = -diagonal;
  else if (direction == "UPLEFT") g.offsetYaw = diagonal, g.offsetPitch = -diagonal;
  else if (direction == "DOWNRIGHT") g.offsetYaw = -diagonal, g.offsetPitch = diagonal;
  else if (direction == "DOWNLEFT") g.offsetYaw = diagonal, g.offsetPitch = diagonal;
  else if (offset != 0.0f)
    warning = "offsetDirection '" + direction.substr(0, 40) + "' is not one of RIGHT, LEFT, UP, DOWN, UPRIGHT, UPLEFT, "
              "DOWNRIGHT, DOWNLEFT; the offset was ignored";
  e.controller = std::move(g);
  return {};
}

}  // namespace marionette
