#include "marionette/bml/behavior_parameters.hpp"

#include "marionette/core/float_chars.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "marionette/behavior/speech_controller.hpp"  // the rate's range
#include "marionette/core/number_list.hpp"
#include "marionette/core/text.hpp"
#include "marionette/core/enum_names.hpp"

namespace marionette::bml {

namespace {

// BML's names (any letter case).
constexpr EnumName<HeadLexeme> kHeadLexemes[] = {
    {"NOD", HeadLexeme::Nod},       {"SHAKE", HeadLexeme::Shake},   {"TILT", HeadLexeme::Tilt},
    {"TOSS", HeadLexeme::Toss},     {"WIGGLE", HeadLexeme::Wiggle}, {"WAGGLE", HeadLexeme::Waggle}};
constexpr const char* kHeadDirections =
    "a direction (UP, DOWN, LEFT, RIGHT, ASIDE_LEFT, ASIDE_RIGHT, TILT_LEFT, TILT_RIGHT and their combinations, "
    "as Greta names them: DOWN_ASIDE_RIGHT, UP_TILT_LEFT, ...)";
constexpr EnumName<GazeInfluence> kGazeInfluences[] = {
    {"EYES", GazeInfluence::Eyes},   {"HEAD", GazeInfluence::Head},   {"NECK", GazeInfluence::Neck},
    {"SHOULDER", GazeInfluence::Shoulder}, {"WAIST", GazeInfluence::Waist}, {"WHOLE", GazeInfluence::Whole}};

constexpr double kDegree = 3.14159265358979323846 / 180.0;

std::string_view valueOf(const Behavior& b, std::string_view name) {
  const Attribute* a = b.attribute(name);
  return a ? std::string_view(a->value) : std::string_view();
}

void note(std::string& warning, const std::string& w) { warning += (warning.empty() ? "" : "; ") + w; }

// One number, the whole text; nullopt for anything else (NaN and infinity are numbers here:
// the middleware names them when it checks the range).
std::optional<float> oneNumber(std::string_view text) {
  float v = 0.0f;
  const auto [end, ec] = floatFromChars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return v;
}

std::string notANumber(std::string_view name, std::string_view text, double lo, double hi, const std::string& then) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "%.*s '%.40s' is not a number in [%g, %g]; ", static_cast<int>(name.size()), name.data(),
                std::string(text).c_str(), lo, hi);
  return buf + then;
}

// amount: a number (its range is the middleware's), else the default with a warning.
float amountOf(const Behavior& b, float fallback, float lo, float hi, std::string& warning) {
  const std::string_view text = valueOf(b, "amount");
  if (text.empty()) return fallback;
  if (const auto v = oneNumber(text)) return *v;
  char then[40];
  std::snprintf(then, sizeof then, "%g is used", static_cast<double>(fallback));
  note(warning, notANumber("amount", text, lo, hi, then));
  return fallback;
}

void readHead(const Behavior& b, ReadParameters& out) {
  const std::string_view lexeme = valueOf(b, "lexeme");
  const float amount =
      amountOf(b, HeadParameters::kDefaultAmount, HeadParameters::kMinAmount, HeadParameters::kMaxAmount, out.warning);
  if (const auto head = headLexemeFromName(lexeme)) {
    out.parameters = HeadParameters{*head, amount};
    return;
  }
  if (const auto direction = headDirectionFromName(lexeme)) {
    out.parameters = HeadParameters{HeadLexeme::Orient, amount, *direction};
    return;
  }
  out.error = (lexeme.empty() ? "a head behavior needs a lexeme (" : "head lexeme '" + std::string(lexeme) + "' is neither ") +
              validNames<HeadLexeme>(kHeadLexemes) + " nor " + kHeadDirections + (lexeme.empty() ? ")" : "");
}

void readFace(const Behavior& b, BehaviorKind kind, ReadParameters& out) {
  FaceParameters f;
  if (kind == BehaviorKind::FaceFacs) {
    const std::string_view au = valueOf(b, "au");
    if (au.empty()) {
      out.error = "a faceFacs behavior needs an au (a FACS action unit number)";
      return;
    }
    f.expression = "AU" + std::string(au);
    // BML's side (LEFT, RIGHT, BOTH: the character's own) picks one side of the unit.
    if (const std::string side = toUpper(std::string(valueOf(b, "side"))); side == "LEFT" || side == "RIGHT")
      f.expression += side == "LEFT" ? "_L" : "_R";
    else if (!side.empty() && side != "BOTH")
      out.warning += (out.warning.empty() ? "" : "; ") + std::string("side=\"") + std::string(valueOf(b, "side")).substr(0, 40) +
                     "\" is not LEFT, RIGHT or BOTH; both sides are used";
  } else {
    f.expression = toUpper(valueOf(b, "lexeme"));
    if (f.expression.empty()) {
      out.error = "a face behavior needs a lexeme";
      return;
    }
  }
  f.amount = amountOf(b, FaceParameters::kDefaultAmount, FaceParameters::kMinAmount, FaceParameters::kMaxAmount, out.warning);
  out.parameters = std::move(f);
}

void readGaze(const Behavior& b, ReadParameters& out) {
  GazeParameters g;
  g.target = readTarget(valueOf(b, "target"));
  if (const std::string_view influence = valueOf(b, "influence"); !influence.empty()) {
    if (auto i = gazeInfluenceFromName(influence)) g.influence = *i;
    else note(out.warning, "influence '" + std::string(influence).substr(0, 40) +
                               "' is not EYES, HEAD, NECK, SHOULDER, WAIST or WHOLE; NECK is used");
  }
  // offsetAngle (degrees) toward offsetDirection, in the character's yaw (left +) and pitch (down +).
  float offset = 0.0f;
  if (const std::string_view text = valueOf(b, "offsetAngle"); !text.empty()) {
    const auto v = oneNumber(text);
    if (v && std::isfinite(*v) && std::fabs(*v) <= 180.0f) offset = static_cast<float>(*v * kDegree);
    else note(out.warning, "offsetAngle '" + std::string(text).substr(0, 40) + "' is not an angle in degrees (-180 to 180); 0 is used");
  }
  const std::string direction = toUpper(valueOf(b, "offsetDirection"));
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
    note(out.warning, "offsetDirection '" + direction.substr(0, 40) +
                          "' is not one of RIGHT, LEFT, UP, DOWN, UPRIGHT, UPLEFT, DOWNRIGHT, DOWNLEFT; the offset was ignored");
  out.parameters = std::move(g);
}

// A pointing's or gesture's mode: which hands; anything else is Nearest, said with `otherwise`.
PointingArms handsOf(const Behavior& b, const char* otherwise, std::string& warning) {
  const std::string mode = toUpper(valueOf(b, "mode"));
  if (mode == "LEFT_HAND") return PointingArms::Left;
  if (mode == "RIGHT_HAND") return PointingArms::Right;
  if (mode == "BOTH_HANDS") return PointingArms::Both;
  if (!mode.empty())
    note(warning, "mode '" + mode.substr(0, 40) + "' is not LEFT_HAND, RIGHT_HAND or BOTH_HANDS; " + otherwise);
  return PointingArms::Nearest;
}

void readPointing(const Behavior& b, ReadParameters& out) {
  PointingParameters p;
  p.target = readTarget(valueOf(b, "target"));
  p.arms = handsOf(b, "the arm on the target's side points", out.warning);
  out.parameters = std::move(p);
}

// A reach (SmartBody's <sbm:reach>, its sbm: attributes without the prefix; Marionette's
// <reach target mode>). SmartBody's point-at is a pointing (PointingParameters).
void readReach(const Behavior& b, ReadParameters& out) {
  ReachParameters r;
  r.target = readTarget(valueOf(b, "target"));
  if (const std::string_view pos = valueOf(b, "target-pos"); !pos.empty()) {  // SmartBody: "x y z", y up
    const auto v = parseNumberList(pos);
    if (!r.target.empty()) note(out.warning, "sbm:target-pos ignored: target names the target");
    else if (v && v->size() == 3) r.target = BehaviorTarget::at({(*v)[0], (*v)[1], (*v)[2]});
    else note(out.warning, "sbm:target-pos '" + std::string(pos.substr(0, 40)) + "' is not three numbers x y z; ignored");
  }
  const std::string type = toUpper(valueOf(b, "reach-type"));
  if (type == "LEFT") r.arm = PointingArms::Left;
  else if (type == "RIGHT") r.arm = PointingArms::Right;
  else if (!type.empty() && type != "NONE")
    note(out.warning, "sbm:reach-type '" + type.substr(0, 40) + "' is not left or right; the arm on the target's side reaches");
  if (!valueOf(b, "mode").empty()) r.arm = handsOf(b, "the arm on the target's side reaches", out.warning);
  const std::string action = toUpper(valueOf(b, "action"));
  if (action == "PICK-UP") r.action = ReachAction::PickUp;
  else if (action == "PUT-DOWN") r.action = ReachAction::PutDown;
  else if (!action.empty() && action != "TOUCH" && action != "POINT-AT")
    note(out.warning, "sbm:action '" + action.substr(0, 40) + "' is not touch, pick-up, put-down or point-at; touch is used");
  const std::string finish = toUpper(valueOf(b, "reach-finish"));
  if (finish == "FALSE")
    note(out.warning, "sbm:reach-finish=\"false\" (hold until a later reach) is not kept: the hand returns by the reach's end");
  else if (!finish.empty() && finish != "TRUE")
    note(out.warning, "sbm:reach-finish '" + finish.substr(0, 40) + "' is not true or false; the hand returns by the reach's end");
  if (equalsIgnoringCase(valueOf(b, "use-locomotion"), "true"))
    note(out.warning, "sbm:use-locomotion: the character does not walk to the target; it reaches from where it stands");
  if (const std::string_view d = valueOf(b, "reach-duration"); !d.empty()) {
    const auto v = oneNumber(d);
    if (!v || !(*v > 0.0f && *v <= 3600.0f)) note(out.warning, notANumber("sbm:reach-duration", d, 0.0, 3600.0, "1 s is used"));
  }
  std::string ignored;
  for (const char* name : {"handle", "reach-velocity", "grab-speed", "cons-joint", "cons-target", "fade-in", "fade-out"})
    if (b.attribute(name)) ignored += (ignored.empty() ? "sbm:" : ", sbm:") + std::string(name);
  if (!ignored.empty()) note(out.warning, ignored + " ignored (the reach is timed by its sync points; nothing is grasped)");
  if (r.target.empty() && r.action != ReachAction::PutDown) {  // put-down: SmartBody's place in front
    out.error = finish == "TRUE" ? "a reach without a target: SmartBody's sbm:reach-finish ends a held reach, and reaches "
                                   "here return by their own end, so there is nothing to do"
                                 : "a reach needs a target: an object, a character (name or name:joint), or \"x y z\"";
    return;
  }
  if (action == "POINT-AT") {
    out.parameters = PointingParameters{r.target, r.arm};
    return;
  }
  out.parameters = std::move(r);
}

// A gesture the character has no clip for: the procedural set's lexeme, the hands (mode),
// and for DEICTIC / POINT a target.
void readGesture(const Behavior& b, ReadParameters& out) {
  GestureParameters g;
  g.lexeme = std::string(valueOf(b, "lexeme"));
  g.target = readTarget(valueOf(b, "target"));
  g.hands = handsOf(b, "the gesture's own hands are used", out.warning);
  out.parameters = std::move(g);
}

// SmartBody's <saccade>: mode (talk, listen, think), finish="true", or direction and magnitude.
void readSaccade(const Behavior& b, ReadParameters& out) {
  SaccadeParameters s;
  const std::string mode = toUpper(valueOf(b, "mode"));
  if (mode == "TALK") s.mode = SaccadeMode::Talk;
  else if (mode == "LISTEN") s.mode = SaccadeMode::Listen;
  else if (mode == "THINK") s.mode = SaccadeMode::Think;
  else if (!mode.empty()) note(out.warning, "saccade mode '" + mode.substr(0, 40) + "' is not TALK, LISTEN or THINK; TALK is used");
  if (!mode.empty() && s.mode == SaccadeMode::None) s.mode = SaccadeMode::Talk;
  s.finish = equalsIgnoringCase(valueOf(b, "finish"), "true");
  auto angle = [&](std::string_view name, float lo, float hi) {
    const std::string_view text = valueOf(b, name);
    if (text.empty()) return 0.0f;
    const auto v = oneNumber(text);
    if (v && std::isfinite(*v) && *v >= lo && *v <= hi) return *v;
    note(out.warning, notANumber(name, text, lo, hi, "0 is used"));
    return 0.0f;
  };
  s.directionDegrees = angle("direction", -360.0f, 360.0f);
  s.magnitudeDegrees = angle("magnitude", -SaccadeParameters::kMaxMagnitudeDegrees, SaccadeParameters::kMaxMagnitudeDegrees);
  if (s.mode == SaccadeMode::None && !s.finish && valueOf(b, "magnitude").empty())
    note(out.warning, "a saccade without mode, finish or magnitude moves nothing");
  out.parameters = s;
}

// AsapRealizer's emitters (bmlt:blinkemitter, bmlt:breathingemitter): avgwaitingtime, the mean
// seconds between blinks or breaths (0 stops the emitter), and range, the half-width of their
// uniform spread around it. A value that is not a number >= 0 is named with the value used.
struct EmitterTimes {
  std::optional<float> average, range;
  bool stop = false;
};
EmitterTimes readEmitterTimes(const Behavior& b, const char* what, float defaultAverage, const char* defaultRange,
                              std::string& warning) {
  EmitterTimes t;
  char then[80];
  if (const std::string_view text = valueOf(b, "avgwaitingtime"); !text.empty()) {
    const auto v = oneNumber(text);
    if (v && std::isfinite(*v) && *v >= 0.0f) {
      t.average = *v;
      t.stop = *v == 0.0f;
    } else {
      std::snprintf(then, sizeof then, "the %s's default %g s is used", what, static_cast<double>(defaultAverage));
      note(warning, notANumber("avgwaitingtime", text, 0.0, 600.0, then));
    }
  }
  if (const std::string_view text = valueOf(b, "range"); !text.empty()) {
    const auto v = oneNumber(text);
    const float average = t.average.value_or(defaultAverage);
    if (!v || !std::isfinite(*v) || *v < 0.0f) {
      note(warning, notANumber("range", text, 0.0, average, std::string("the default spread, ") + defaultRange + ", is used"));
    } else if (*v >= average && !t.stop) {
      std::snprintf(then, sizeof then, "%g", static_cast<double>(average));
      note(warning, "range '" + std::string(text.substr(0, 40)) + "' is not below avgwaitingtime " + then +
                        " (AsapRealizer requires it); " + then + " is used");
      t.range = average;
    } else {
      t.range = *v;
    }
  }
  return t;
}

// The same spread as AsapRealizer's uniform avg +- range (standard deviation range / sqrt 3),
// as the log-normal's coefficient of variation.
void readBlinkEmitter(const Behavior& b, ReadParameters& out) {
  BlinkParameters p;
  const EmitterTimes t = readEmitterTimes(b, "blink emitter", p.meanIntervalSeconds, "variation 0.6", out.warning);
  p.stop = t.stop;
  if (t.average && !t.stop) p.meanIntervalSeconds = *t.average;
  if (t.range && !t.stop) p.variation = *t.range / (std::sqrt(3.0f) * p.meanIntervalSeconds);
  out.parameters = p;
}

void readBreathingEmitter(const Behavior& b, ReadParameters& out) {
  BreathingParameters p;
  const EmitterTimes t = readEmitterTimes(b, "breathing emitter", 60.0f / p.breathsPerMinute, "0 s", out.warning);
  p.stop = t.stop;
  if (t.average && !t.stop) p.breathsPerMinute = 60.0f / *t.average;
  if (t.range && !t.stop) p.periodRangeSeconds = *t.range;
  if (const std::string_view text = valueOf(b, "amplitude"); !text.empty()) {
    // A number goes to the emitter, which clamps it with a warning; anything else is named here.
    if (const auto v = oneNumber(text)) p.amplitudeDegrees = *v;
    else note(out.warning, notANumber("amplitude", text, 0.0, BreathingParameters::kMaxAmplitudeDegrees,
                                      "the default 1.5 degrees is used"));
  }
  out.parameters = p;
}

void readLocomotion(const Behavior& b, ReadParameters& out) {
  LocomotionParameters l;
  const std::string_view target = valueOf(b, "target");
  if (target.empty()) {
    out.error = "a locomotion needs a target: \"x z\" in metres, waypoints \"x1 z1 x2 z2 ...\", or a character";
    return;
  }
  const std::string shown(target.substr(0, 60));
  if (const auto numbers = parseNumberList(target)) {
    const std::vector<float>& v = *numbers;
    for (float x : v)
      if (!std::isfinite(x)) {
        out.error = "locomotion target '" + shown + "' is not finite (NaN or infinite); nothing moves";
        return;
      }
    if (v.size() == 3) {
      l.waypoints.push_back({v[0], v[2]});  // x y z: y (up) is ignored
      if (v[1] != 0.0f && v[1] != v[2]) {  // which convention was meant is not sure: say which was taken
        char buf[240];
        std::snprintf(buf, sizeof buf,
                      "locomotion target '%s' is read as BML's x y z (y up): the ground point x=%g, z=%g, its height %g "
                      "dropped (SmartBody's z-up reading, in its dialect, would be x=%g, z=%g)",
                      shown.c_str(), static_cast<double>(v[0]), static_cast<double>(v[2]), static_cast<double>(v[1]),
                      static_cast<double>(v[0]), static_cast<double>(v[1]));
        note(out.warning, buf);
      }
    } else if (v.size() >= 2 && v.size() % 2 == 0 && v.size() / 2 <= LocomotionParameters::kMaxWaypoints) {
      for (std::size_t i = 0; i < v.size(); i += 2) l.waypoints.push_back({v[i], v[i + 1]});
    } else {
      out.error = "locomotion target '" + shown + "' has " + std::to_string(v.size()) +
                  " numbers: give \"x z\", \"x y z\", or up to 1000 waypoints \"x1 z1 x2 z2 ...\"";
      return;
    }
  } else {
    l.targetCharacter = std::string(target.substr(0, target.find(':')));
  }
  const std::string manner = toUpper(valueOf(b, "manner"));
  if (manner == "RUN" || manner == "JOG") l.manner = LocomotionManner::Run;
  else if (manner == "STROLL") l.manner = LocomotionManner::Stroll;
  else if (manner == "SPRINT") l.manner = LocomotionManner::Sprint;
  else if (!manner.empty() && manner != "WALK")
    note(out.warning, "manner '" + manner.substr(0, 40) + "' is not WALK, RUN, JOG, STROLL or SPRINT; WALK is used");
  // A number, else ignored with a warning; the middleware checks the range of speed and
  // proximity, facing (degrees here) is checked in BML's unit.
  auto number = [&](std::string_view name, double lo, double hi) -> std::optional<float> {
    const std::string_view text = valueOf(b, name);
    if (text.empty()) return std::nullopt;
    const auto v = parseNumberList(text);
    if (!v || v->size() != 1) {
      note(out.warning, notANumber(name, text, lo, hi, "ignored"));
      return std::nullopt;
    }
    return v->front();
  };
  l.speed = number("speed", LocomotionParameters::kMinSpeed, LocomotionParameters::kMaxSpeed);
  l.proximity = number("proximity", 0.0, LocomotionParameters::kMaxProximity);
  if (const auto facing = number("facing", -360.0, 360.0)) {
    if (std::isfinite(*facing) && std::fabs(*facing) <= 360.0f) l.facing = static_cast<float>(*facing * kDegree);
    else note(out.warning, notANumber("facing", valueOf(b, "facing"), -360.0, 360.0, "ignored"));
  }
  out.parameters = std::move(l);
}

void readSpeech(const Behavior& b, ReadParameters& out) {
  SpeechParameters s;
  s.text = b.text;
  s.voice = std::string(valueOf(b, "voice"));
  for (const WordMark& m : b.marks) s.marks.push_back({m.id, m.characterOffset});
  if (const std::string_view rate = valueOf(b, "rate"); !rate.empty()) {
    const auto v = oneNumber(rate);
    if (v && std::isfinite(*v) && *v >= static_cast<float>(kMinWordsPerMinute) && *v <= static_cast<float>(kMaxWordsPerMinute))
      s.wordsPerMinute = static_cast<int>(std::lround(*v));
    else note(out.warning, "speech rate '" + std::string(rate) +
                               "' is not a number of words per minute in [1, 10000]; the voice's default is used");
  }
  out.parameters = std::move(s);
}

}  // namespace

std::optional<HeadLexeme> headLexemeFromName(std::string_view name) noexcept {
  return valueOfName<HeadLexeme>(name, kHeadLexemes, NameCase::Ignored);
}

std::optional<glm::vec3> headDirectionFromName(std::string_view name) {
  // Words split by '_', '-' or spaces, any case. At BML's default amount (0.5, half of these):
  // UP / DOWN pitch 15 / 20 degrees, LEFT / RIGHT and ASIDE_LEFT / ASIDE_RIGHT turn 25,
  // TILT_LEFT / TILT_RIGHT roll 15 (the character's own sides).
  std::vector<std::string> words;
  std::string word;
  for (const char c : name) {
    if (c == '_' || c == '-' || c == ' ') {
      if (!word.empty()) words.push_back(std::move(word)), word.clear();
    } else {
      word += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
  }
  if (!word.empty()) words.push_back(std::move(word));
  glm::vec3 degrees(0.0f);
  bool any = false;
  for (std::size_t i = 0; i < words.size(); ++i) {
    const std::string& w = words[i];
    const bool sided = (w == "TILT" || w == "ASIDE") && i + 1 < words.size() && (words[i + 1] == "LEFT" || words[i + 1] == "RIGHT");
    if (w == "UP") degrees.x -= 30.0f;
    else if (w == "DOWN") degrees.x += 40.0f;
    else if (w == "LEFT") degrees.y += 50.0f;
    else if (w == "RIGHT") degrees.y -= 50.0f;
    else if (sided && w == "TILT") degrees.z += words[++i] == "LEFT" ? -30.0f : 30.0f;
    else if (sided && w == "ASIDE") degrees.y += words[++i] == "LEFT" ? 50.0f : -50.0f;
    else return std::nullopt;
    any = true;
  }
  if (!any) return std::nullopt;
  return degrees;
}

std::optional<GazeInfluence> gazeInfluenceFromName(std::string_view name) noexcept {
  return valueOfName<GazeInfluence>(name, kGazeInfluences, NameCase::Ignored);
}

BehaviorTarget readTarget(std::string_view text) {
  if (text.empty()) return {};
  if (const auto v = parseNumberList(text); v && v->size() == 3) return BehaviorTarget::at({(*v)[0], (*v)[1], (*v)[2]});
  const std::size_t colon = text.find(':');
  return BehaviorTarget::of(std::string(text.substr(0, colon)),
                            colon == std::string_view::npos ? std::string() : std::string(text.substr(colon + 1)));
}

ReadParameters readParameters(const Behavior& b, BehaviorKind kind) {
  ReadParameters out;
  switch (kind) {
    case BehaviorKind::Head: readHead(b, out); break;
    case BehaviorKind::FaceLexeme:
    case BehaviorKind::FaceFacs:
    case BehaviorKind::Face:
    case BehaviorKind::FaceShift: readFace(b, kind, out); break;
    case BehaviorKind::Gaze:
    case BehaviorKind::GazeShift:
    case BehaviorKind::HeadDirectionShift: readGaze(b, out); break;
    case BehaviorKind::Pointing: readPointing(b, out); break;
    case BehaviorKind::Gesture: readGesture(b, out); break;
    case BehaviorKind::Saccade: readSaccade(b, out); break;
    case BehaviorKind::BlinkEmitter: readBlinkEmitter(b, out); break;
    case BehaviorKind::BreathingEmitter: readBreathingEmitter(b, out); break;
    case BehaviorKind::Reach: readReach(b, out); break;
    case BehaviorKind::Locomotion: readLocomotion(b, out); break;
    case BehaviorKind::Speech: readSpeech(b, out); break;
    default: break;  // postures, waits and clips have no parameters
  }
  if (!out.error.empty()) out.parameters = std::monostate{};
  return out;
}

}  // namespace marionette::bml
