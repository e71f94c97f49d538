// FACS on any face: action units (AU12, AU45_L, ...) and the named expressions made of them
// (WINK, RAISE_LEFT_BROW, SMILE, ...), and the table from each unit to what characters carry
// instead of AU morphs: ARKit's 52 blendshape names, VRM expressions, eyelid and brow joints
// (docs/controllers.md, "FACS on any face"). The profile guess resolves each unit once per
// character (profile_guess_facs.cpp); the face controller uses what was resolved.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace marionette {

// One action unit as asked: its number, the side (-1 the character's left, +1 its right,
// 0 both) and a weight in [0, 1] (a named expression's share of the unit).
struct FacsUnitRequest {
  int au = 0;
  int side = 0;
  float amount = 1.0f;
};

// "AU12", "au12", "12", "AU12_L", "AU12L", "AU12_LEFT", "AU1_RIGHT": one unit, else nothing.
[[nodiscard]] std::optional<FacsUnitRequest> parseFacsUnit(std::string_view name);
// A unit, or a named expression (facsExpressions()) as its units; empty when it is neither.
[[nodiscard]] std::vector<FacsUnitRequest> facsUnitsOf(std::string_view expression);
// The key of a unit in a profile's face and facs tables: "AU12", "AU12_L", "AU12_R".
[[nodiscard]] std::string facsKey(int au, int side);

// How a unit moves an eyelid or a brow joint when the face has no morph for it: an upper
// lid turns about the character's left axis (positive closes), a brow rises by a share of the
// eyes' height above the ground (negative lowers it).
enum class FacsFacePart : std::uint8_t { UpperLid, Brow };
struct FacsJointRule {
  FacsFacePart part = FacsFacePart::UpperLid;
  float closeDegrees = 0.0f;  // UpperLid
  float liftShare = 0.0f;     // Brow: of the eye height (0.006 of 1.6 m is 1 cm)
};

// A weighted name: an ARKit blendshape ("mouthSmile*": * is Left or Right, both for a unit
// asked on both sides) or a VRM expression preset ("blink*": *_l / *left and *_r / *right).
struct FacsTarget {
  const char* name;
  float weight;
};

struct FacsUnitInfo {
  int au;
  const char* name;  // FACS's name ("Lip Corner Puller")
  bool sided;        // the face shows it on each side apart
  std::vector<FacsTarget> arkit;
  std::vector<FacsTarget> vrm;
  std::optional<FacsJointRule> joint;
};

// The units this table knows, by number.
[[nodiscard]] const std::vector<FacsUnitInfo>& facsUnits();
[[nodiscard]] const FacsUnitInfo* facsUnit(int au);

// Named expressions as units: BML 1.0's face lexemes and emotions (EMFACS prototypes),
// SmartBody's and Greta's (WINK, BLINK, RAISE_LEFT_BROW, ...).
struct FacsExpression {
  const char* name;
  std::vector<FacsUnitRequest> units;
};
[[nodiscard]] const std::vector<FacsExpression>& facsExpressions();

}  // namespace marionette
