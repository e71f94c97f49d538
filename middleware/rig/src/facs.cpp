#include "marionette/rig/facs.hpp"

#include <algorithm>
#include <cctype>

#include "marionette/core/text.hpp"

namespace marionette {

namespace {

bool isDigitChar(char c) { return c >= '0' && c <= '9'; }

// The side written after a unit's number: "", "L", "_L", "LEFT", "_LEFT" (any case).
std::optional<int> sideSuffix(std::string_view s) {
  if (!s.empty() && (s.front() == '_' || s.front() == '-')) s.remove_prefix(1);
  const std::string up = toUpper(std::string(s));
  if (up.empty()) return 0;
  if (up == "L" || up == "LEFT") return -1;
  if (up == "R" || up == "RIGHT") return 1;
  return std::nullopt;
}

}  // namespace

std::optional<FacsUnitRequest> parseFacsUnit(std::string_view name) {
  if (name.size() >= 2 && (name[0] == 'A' || name[0] == 'a') && (name[1] == 'U' || name[1] == 'u')) name.remove_prefix(2);
  std::size_t digits = 0;
  while (digits < name.size() && isDigitChar(name[digits])) ++digits;
  if (digits == 0 || digits > 2) return std::nullopt;
  const int au = std::stoi(std::string(name.substr(0, digits)));
  const auto side = sideSuffix(name.substr(digits));
  if (!side || au <= 0) return std::nullopt;
  return FacsUnitRequest{au, *side, 1.0f};
}

std::string facsKey(int au, int side) {
  return "AU" + std::to_string(au) + (side < 0 ? "_L" : side > 0 ? "_R" : "");
}

std::vector<FacsUnitRequest> facsUnitsOf(std::string_view expression) {
  if (auto unit = parseFacsUnit(expression)) return {*unit};
  const std::string up = toUpper(std::string(expression));
  for (const FacsExpression& e : facsExpressions())
    if (up == e.name) return e.units;
  return {};
}

// The table. ARKit names are Apple's ARFaceAnchor.BlendShapeLocation; VRM presets are 0.x's
// and 1.0's. The pairings follow FACS's descriptions of each unit (Ekman, Friesen and Hager,
// 2002) and the ARKit shapes' own descriptions; a VRM preset stands for a unit only where the
// preset's look is mainly that unit (Joy for AU12, Sorrow for AU15, Blink for AU45), at a
// weight below 1 where the preset does more than the unit.
const std::vector<FacsUnitInfo>& facsUnits() {
  using R = FacsJointRule;
  static const std::vector<FacsUnitInfo> units = {
      {1, "Inner Brow Raiser", false, {{"browInnerUp", 1.0f}}, {{"surprised", 0.5f}}, R{FacsFacePart::Brow, 0.0f, 0.006f}},
      {2, "Outer Brow Raiser", true, {{"browOuterUp*", 1.0f}}, {{"surprised", 0.5f}}, R{FacsFacePart::Brow, 0.0f, 0.006f}},
      {4, "Brow Lowerer", true, {{"browDown*", 1.0f}}, {{"angry", 0.6f}}, R{FacsFacePart::Brow, 0.0f, -0.004f}},
      {5, "Upper Lid Raiser", true, {{"eyeWide*", 1.0f}}, {{"surprised", 0.4f}}, R{FacsFacePart::UpperLid, -10.0f, 0.0f}},
      {6, "Cheek Raiser", true, {{"cheekSquint*", 1.0f}}, {{"joy", 0.5f}, {"happy", 0.5f}}, std::nullopt},
      {7, "Lid Tightener", true, {{"eyeSquint*", 1.0f}}, {{"angry", 0.3f}}, R{FacsFacePart::UpperLid, 12.0f, 0.0f}},
      {9, "Nose Wrinkler", true, {{"noseSneer*", 1.0f}}, {{"angry", 0.4f}}, std::nullopt},
      {10, "Upper Lip Raiser", true, {{"mouthUpperUp*", 1.0f}}, {}, std::nullopt},
      {12, "Lip Corner Puller", true, {{"mouthSmile*", 1.0f}}, {{"joy", 1.0f}, {"happy", 1.0f}}, std::nullopt},
      {13, "Cheek Puffer", false, {{"cheekPuff", 1.0f}}, {}, std::nullopt},
      {14, "Dimpler", true, {{"mouthDimple*", 1.0f}}, {}, std::nullopt},
      {15, "Lip Corner Depressor", true, {{"mouthFrown*", 1.0f}}, {{"sorrow", 1.0f}, {"sad", 1.0f}}, std::nullopt},
      {16, "Lower Lip Depressor", true, {{"mouthLowerDown*", 1.0f}}, {}, std::nullopt},
      {17, "Chin Raiser", false, {{"mouthShrugLower", 1.0f}}, {}, std::nullopt},
      {18, "Lip Pucker", false, {{"mouthPucker", 1.0f}}, {{"u", 1.0f}, {"ou", 1.0f}}, std::nullopt},
      {19, "Tongue Show", false, {{"tongueOut", 1.0f}}, {}, std::nullopt},
      {20, "Lip Stretcher", true, {{"mouthStretch*", 1.0f}}, {{"e", 0.5f}, {"ee", 0.5f}}, std::nullopt},
      {22, "Lip Funneler", false, {{"mouthFunnel", 1.0f}}, {{"o", 1.0f}, {"oh", 1.0f}}, std::nullopt},
      {23, "Lip Tightener", true, {{"mouthPress*", 0.6f}}, {}, std::nullopt},
      {24, "Lip Pressor", true, {{"mouthPress*", 1.0f}}, {}, std::nullopt},
      {25, "Lips Part", false, {{"jawOpen", 0.2f}}, {{"a", 0.25f}, {"aa", 0.25f}}, std::nullopt},
      {26, "Jaw Drop", false, {{"jawOpen", 0.6f}}, {{"a", 0.7f}, {"aa", 0.7f}}, std::nullopt},
      {27, "Mouth Stretch", false, {{"jawOpen", 1.0f}}, {{"a", 1.0f}, {"aa", 1.0f}}, std::nullopt},
      {28, "Lip Suck", false, {{"mouthRollLower", 1.0f}, {"mouthRollUpper", 1.0f}}, {}, std::nullopt},
      {43, "Eyes Closed", true, {{"eyeBlink*", 1.0f}}, {{"blink*", 1.0f}}, R{FacsFacePart::UpperLid, 35.0f, 0.0f}},
      {45, "Blink", true, {{"eyeBlink*", 1.0f}}, {{"blink*", 1.0f}}, R{FacsFacePart::UpperLid, 35.0f, 0.0f}},
      {46, "Wink", true, {{"eyeBlink*", 1.0f}}, {{"blink*", 1.0f}}, R{FacsFacePart::UpperLid, 35.0f, 0.0f}},
  };
  return units;
}

const FacsUnitInfo* facsUnit(int au) {
  const auto& units = facsUnits();
  const auto it = std::find_if(units.begin(), units.end(), [&](const FacsUnitInfo& u) { return u.au == au; });
  return it == units.end() ? nullptr : &*it;
}

// BML 1.0's face lexemes with their FACS column, the emotions as EMFACS prototypes (Friesen
// and Ekman, 1983), and the names other realizers' scripts use (SmartBody, Greta).
const std::vector<FacsExpression>& facsExpressions() {
  using U = FacsUnitRequest;
  static const std::vector<FacsExpression> expressions = {
      {"OBLIQUE_BROWS", {U{1, 0, 1.0f}}},
      {"RAISE_BROWS", {U{1, 0, 1.0f}, U{2, 0, 1.0f}}},
      {"RAISE_LEFT_BROW", {U{1, -1, 1.0f}, U{2, -1, 1.0f}}},
      {"RAISE_RIGHT_BROW", {U{1, 1, 1.0f}, U{2, 1, 1.0f}}},
      {"LOWER_BROWS", {U{4, 0, 1.0f}}},
      {"LOWER_LEFT_BROW", {U{4, -1, 1.0f}}},
      {"LOWER_RIGHT_BROW", {U{4, 1, 1.0f}}},
      {"LOWER_MOUTH_CORNERS", {U{15, 0, 1.0f}}},
      {"LOWER_LEFT_MOUTH_CORNER", {U{15, -1, 1.0f}}},
      {"LOWER_RIGHT_MOUTH_CORNER", {U{15, 1, 1.0f}}},
      {"RAISE_MOUTH_CORNERS", {U{12, 0, 1.0f}}},
      {"RAISE_LEFT_MOUTH_CORNER", {U{12, -1, 1.0f}}},
      {"RAISE_RIGHT_MOUTH_CORNER", {U{12, 1, 1.0f}}},
      {"OPEN_MOUTH", {U{26, 0, 1.0f}}},
      {"OPEN_LIPS", {U{25, 0, 1.0f}}},
      {"WIDEN_EYES", {U{5, 0, 1.0f}}},
      {"CLOSE_EYES", {U{43, 0, 1.0f}}},
      {"EYE_SQUINT", {U{7, 0, 1.0f}}},
      {"BARE_TEETH", {U{10, 0, 1.0f}, U{25, 0, 1.0f}}},
      {"BARE_TEETH_WIDE", {U{10, 0, 1.0f}, U{20, 0, 1.0f}, U{25, 0, 1.0f}}},
      {"PRESS_LIPS", {U{24, 0, 1.0f}}},
      {"PUCKER_LIPS", {U{18, 0, 1.0f}}},
      {"TONGUE_OUT", {U{19, 0, 1.0f}, U{25, 0, 1.0f}}},
      {"BLINK", {U{45, 0, 1.0f}}},
      {"WINK", {U{46, -1, 1.0f}}},
      {"WINK_LEFT", {U{46, -1, 1.0f}}},
      {"WINK_RIGHT", {U{46, 1, 1.0f}}},
      {"SMILE", {U{6, 0, 1.0f}, U{12, 0, 1.0f}}},
      {"SADNESS", {U{1, 0, 1.0f}, U{4, 0, 1.0f}, U{15, 0, 1.0f}}},
      {"SURPRISE", {U{1, 0, 1.0f}, U{2, 0, 1.0f}, U{5, 0, 0.5f}, U{26, 0, 1.0f}}},
      {"FEAR", {U{1, 0, 1.0f}, U{2, 0, 1.0f}, U{4, 0, 1.0f}, U{5, 0, 1.0f}, U{7, 0, 1.0f}, U{20, 0, 1.0f}, U{26, 0, 1.0f}}},
      {"ANGER", {U{4, 0, 1.0f}, U{5, 0, 1.0f}, U{7, 0, 1.0f}, U{23, 0, 1.0f}}},
      {"DISGUST", {U{9, 0, 1.0f}, U{15, 0, 1.0f}, U{16, 0, 1.0f}}},
      {"CONTEMPT", {U{12, 1, 0.5f}, U{14, 1, 0.5f}}},
  };
  return expressions;
}

}  // namespace marionette
