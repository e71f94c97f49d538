#include "marionette/behavior/procedural_controllers.hpp"

#include "marionette/core/text.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cmath>

namespace marionette {

namespace {
// An amount in [lo, hi]; anything else is replaced by the default, with a note.
float checkedAmount(float v, float fallback, float lo, float hi, std::string& warning) {
  if (std::isfinite(v) && v >= lo && v <= hi) return v;
  char buf[160];
  std::snprintf(buf, sizeof buf, "amount '%g' is not a number in [%g, %g]; %g is used", static_cast<double>(v),
                static_cast<double>(lo), static_cast<double>(hi), static_cast<double>(fallback));
  warning = buf;
  return fallback;
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
  const HeadParameters* p = r.as<HeadParameters>();
  if (!p) return "a head behavior needs HeadParameters (a lexeme: NOD, SHAKE, TILT, TOSS, WIGGLE, WAGGLE or a direction)";
  if (rig.joints().head < 0 && rig.joints().neck < 0)
    return "the character has no head or neck joint (set \"head\" in its profile)";
  HeadMotionState h;
  h.lexeme = p->lexeme;
  h.move = headMove(*p);
  if (!(std::isfinite(h.move.degrees.x) && std::isfinite(h.move.degrees.y) && std::isfinite(h.move.degrees.z)))
    return "a head direction's angles are not finite";
  h.amount = checkedAmount(p->amount, HeadParameters::kDefaultAmount, HeadParameters::kMinAmount,
                           HeadParameters::kMaxAmount, warning);
  h.strokes = strokesOf(r);
  // A held direction: to it by ready, held to relax, back by end (BML's default proportions when
  // the request has no such syncs).
  const double start = r.start(), span = r.end() - r.start();
  h.phases = {start, r.time("ready").value_or(start + 0.1 * span), r.time("relax").value_or(start + 0.8 * span), r.end()};
  std::string fitted;
  h.amount = fitHeadToABody(h.move, h.amount, h.strokes, h.phases, fitted);
  if (!fitted.empty()) warning += (warning.empty() ? "" : "; ") + fitted;
  e.controller = std::move(h);
  return {};
}

namespace {

// Adds a unit's morphs and joints to an expression, scaled by the unit's share; false when the
// character shows the unit by nothing. `shownBy` says what shows it.
bool addFacsUnit(const FacsUnitRequest& u, const Rig& rig, FaceExpressionState& f, std::string& shownBy) {
  const RigJoints& j = rig.joints();
  auto fromFace = [&](const std::string& key) {  // the profile's face table: AU morphs by name
    auto it = j.face.find(key);
    if (it == j.face.end() && key.size() > 2 && key[key.size() - 2] == '_')  // "AU12L" for "AU12_L"
      it = j.face.find(key.substr(0, key.size() - 2) + key.back());
    if (it == j.face.end()) return false;
    for (const auto& [morph, amount] : it->second) f.morphs.emplace_back(morph, amount * u.amount);
    shownBy = key + " by AU morphs";
    return true;
  };
  auto fromFacs = [&](const std::string& key, const char* note) {
    const auto it = j.facs.find(key);
    // Joints have sides: a side with none does not borrow the other side's.
    if (it == j.facs.end() || (*note && it->second.morphs.empty())) return false;
    for (const auto& [morph, amount] : it->second.morphs) f.morphs.emplace_back(morph, amount * u.amount);
    for (const RigJoints::FacsJoint& move : it->second.joints) {
      const bool lid = move.rule.part == FacsFacePart::UpperLid;
      f.joints.push_back({move.joint, move.rule.part,
                          u.amount * (lid ? glm::radians(move.rule.closeDegrees) : move.rule.liftShare * j.eyeHeight)});
    }
    shownBy = key + " by " + it->second.source + note;
    return true;
  };
  const std::string key = facsKey(u.au, u.side);
  if (fromFace(key) || fromFacs(key, "")) return true;
  if (u.side != 0) {  // one side asked, only both shown: both, said
    const FacsUnitInfo* info = facsUnit(u.au);
    const char* note = info && !info->sided ? " (one shape for both sides)" : " (both sides: the face has no one-sided shape)";
    return fromFace(facsKey(u.au, 0)) || fromFacs(facsKey(u.au, 0), note);
  }
  // Both sides asked: the left and the right unit together.
  FacsUnitRequest l = u, r = u;
  l.side = -1, r.side = 1;
  const std::size_t morphs = f.morphs.size(), joints = f.joints.size();
  std::string left, right;
  if (addFacsUnit(l, rig, f, left) && addFacsUnit(r, rig, f, right)) {
    shownBy = left + " and " + right;
    return true;
  }
  f.morphs.resize(morphs), f.joints.resize(joints);
  return false;
}

}  // namespace

std::string bindFace(BehaviorTimeline::Entry& e, const Rig& rig, std::string& warning) {
  const FaceParameters* p = e.request.as<FaceParameters>();
  if (!p || p->expression.empty()) return "a face behavior needs FaceParameters with an expression (a lexeme or AUn)";
  const std::string expression = toUpper(p->expression);
  FaceExpressionState f;
  if (const auto it = rig.joints().face.find(expression); it != rig.joints().face.end()) {
    f.morphs = it->second;
  } else {
    // FACS on any face: the expression's units through the character's AU, ARKit or VRM
    // morphs, its profile's facs map, or its eyelid and brow joints.
    const std::vector<FacsUnitRequest> units = facsUnitsOf(expression);
    if (units.empty())
      return "the character has no morphs for face expression '" + expression + "' (" + knownExpressions(rig.joints()) +
             "), and it is neither a FACS unit (AUn, AUn_L, AUn_R) nor an expression of the FACS table";
    std::string shown, missing;
    bool exact = true;  // every unit by AU morphs of its own side: nothing to say
    for (const FacsUnitRequest& u : units) {
      std::string by;
      if (addFacsUnit(u, rig, f, by)) {
        shown += (shown.empty() ? "" : ", ") + by;
        exact = exact && by.ends_with(" by AU morphs");
      } else {
        missing += (missing.empty() ? "" : ", ") + facsKey(u.au, u.side);
      }
    }
    if (f.morphs.empty() && f.joints.empty())
      return "the character has no morphs for face expression '" + expression + "' (" + knownExpressions(rig.joints()) +
             "), and nothing shows its FACS units " + missing +
             " (no AU, ARKit, VRM or expression morphs, no \"facs\" in its profile, no eyelid or brow joints)";
    // Units that share a morph add up, to at most the morph's full weight.
    std::sort(f.morphs.begin(), f.morphs.end());
    std::vector<std::pair<int, float>> merged;
    for (const auto& [morph, amount] : f.morphs) {
      if (!merged.empty() && merged.back().first == morph) merged.back().second += amount;
      else merged.emplace_back(morph, amount);
    }
    for (auto& m : merged) m.second = std::min(m.second, 1.0f);
    f.morphs = std::move(merged);
    if (!exact || !missing.empty())
      warning += (warning.empty() ? "" : "; ") + std::string("face '") + expression + "' is shown through FACS: " + shown +
                 (missing.empty() ? "" : "; not shown (nothing on this face moves it): " + missing);
  }
  f.amount = checkedAmount(p->amount, FaceParameters::kDefaultAmount, FaceParameters::kMinAmount,
                           FaceParameters::kMaxAmount, warning);
  e.controller = std::move(f);
  return {};
}

void applyHead(const HeadMotionState& h, float weight, double t, const Rig& rig, std::span<Transform> pose) noexcept {
  const float shape = headShape(h.move, h.strokes, h.phases, t);
  if (shape == 0.0f) return;
  const glm::vec3 angles = glm::radians(h.move.degrees) * (weight * h.amount * shape);
  const RigJoints& j = rig.joints();
  // The neck takes 40 % and the head the rest, in the model frame, so that the head's whole
  // turn is the move's (head after neck: whole = head * neck).
  if (j.neck >= 0 && j.head >= 0) {
    const glm::quat neck = headRotation(0.4f * angles);
    rotateInModelFrame(rig.skeleton(), pose, j.neck, neck);
    rotateInModelFrame(rig.skeleton(), pose, j.head, headRotation(angles) * glm::inverse(neck));
  } else {
    rotateInModelFrame(rig.skeleton(), pose, j.head >= 0 ? j.head : j.neck, headRotation(angles));
  }
}

void applyFace(const FaceExpressionState& f, float weight, std::span<float> morphWeights, const Rig& rig,
               std::span<Transform> pose) noexcept {
  // Expressions add up, each morph clamped to [0, 1].
  for (const auto& [morph, amount] : f.morphs)
    if (morph >= 0 && static_cast<std::size_t>(morph) < morphWeights.size()) {
      float& w = morphWeights[static_cast<std::size_t>(morph)];
      w = std::clamp(w + weight * f.amount * amount, 0.0f, 1.0f);
    }
  const float share = weight * f.amount;
  for (const FaceExpressionState::JointMove& m : f.joints) {
    if (m.part == FacsFacePart::UpperLid)  // about the character's left: positive turns the lid down
      rotateInModelFrame(rig.skeleton(), pose, m.joint, glm::angleAxis(share * m.value, rig.joints().leftAxis));
    else
      translateInModelFrame(rig.skeleton(), pose, m.joint, glm::vec3(0.0f, share * m.value, 0.0f));
  }
}

std::string bindGaze(BehaviorTimeline::Entry& e, const Rig& rig,
                     const TargetJointFinder& findJoint, std::string& warning) {
  const GazeParameters* p = e.request.as<GazeParameters>();
  GazeState g;
  const RigJoints& j = rig.joints();
  if (j.head < 0 && j.neck < 0 && j.leftEye < 0 && j.rightEye < 0)
    return "the character has no eye, head or neck joint to gaze with (set them in its profile)";
  if (std::string why = resolveSpatialTarget(p ? p->target : BehaviorTarget{}, "gaze", findJoint, g.target); !why.empty())
    return why;
  g.influence = p->influence;
  auto offset = [&](float v, const char* name) {
    if (std::isfinite(v) && std::fabs(v) <= GazeParameters::kMaxOffsetRadians) return v;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s '%g' is not an angle in radians (-pi to pi); 0 is used", name, static_cast<double>(v));
    warning += (warning.empty() ? "" : "; ") + std::string(buf);
    return 0.0f;
  };
  g.offsetYaw = offset(p->offsetYaw, "offsetYaw");
  g.offsetPitch = offset(p->offsetPitch, "offsetPitch");
  e.controller = std::move(g);
  return {};
}

}  // namespace marionette
