// core/enum_names.hpp: the one lookup from names to enum values, and the list of valid names
// that messages give; and the lookups built on it.
#include <gtest/gtest.h>

#include <string>

#include "marionette/behavior/behavior_request.hpp"
#include "marionette/core/enum_names.hpp"
#include "marionette/rig/joint_map.hpp"
#include "marionette/speech/phoneme.hpp"

using namespace marionette;

namespace {
enum class Fruit : std::uint8_t { Apple, Pear, Fig };
constexpr EnumName<Fruit> kFruits[] = {
    {"apple", Fruit::Apple}, {"pear", Fruit::Pear}, {"conference", Fruit::Pear}, {"fig", Fruit::Fig}};
constexpr std::string_view kIndexed[] = {"apple", "pear", "fig"};
}  // namespace

TEST(EnumNames, ExactCaseFindsOnlyTheSpelling) {
  EXPECT_EQ(valueOfName<Fruit>("pear", kFruits), Fruit::Pear);
  EXPECT_EQ(valueOfName<Fruit>("conference", kFruits), Fruit::Pear);  // an alias
  EXPECT_FALSE(valueOfName<Fruit>("Pear", kFruits));
  EXPECT_FALSE(valueOfName<Fruit>("", kFruits));
  EXPECT_FALSE(valueOfName<Fruit>("pears", kFruits));
}

TEST(EnumNames, IgnoredCaseFoldsAsciiLettersOnly) {
  EXPECT_EQ(valueOfName<Fruit>("FIG", kFruits, NameCase::Ignored), Fruit::Fig);
  EXPECT_EQ(valueOfName<Fruit>("Apple", kFruits, NameCase::Ignored), Fruit::Apple);
  EXPECT_FALSE(valueOfName<Fruit>("fig ", kFruits, NameCase::Ignored));
}

TEST(EnumNames, NameOfAValueIsItsFirstName) {
  EXPECT_EQ(nameOfValue<Fruit>(Fruit::Pear, kFruits, "?"), "pear");
  constexpr EnumName<Fruit> noFig[] = {{"apple", Fruit::Apple}};
  EXPECT_EQ(nameOfValue<Fruit>(Fruit::Fig, noFig, "?"), "?");
}

TEST(EnumNames, IndexedTablesNameTheValueOfTheirIndex) {
  EXPECT_EQ(valueOfIndexedName<Fruit>("fig", kIndexed), Fruit::Fig);
  EXPECT_EQ(valueOfIndexedName<Fruit>("PEAR", kIndexed, NameCase::Ignored), Fruit::Pear);
  EXPECT_FALSE(valueOfIndexedName<Fruit>("PEAR", kIndexed));
}

TEST(EnumNames, ValidNamesListEachValueOnceInTableOrder) {
  EXPECT_EQ(validNames<Fruit>(kFruits), "apple, pear or fig");  // the alias is not listed
  constexpr EnumName<Fruit> two[] = {{"apple", Fruit::Apple}, {"fig", Fruit::Fig}};
  EXPECT_EQ(validNames<Fruit>(two), "apple or fig");
  constexpr EnumName<Fruit> one[] = {{"fig", Fruit::Fig}};
  EXPECT_EQ(validNames<Fruit>(one), "fig");
}

TEST(EnumNames, TheLibrarysLookupsRoundTripTheirNames) {
  using retarget::Bone;
  for (int b = 0; b < retarget::kBoneCount; ++b)
    EXPECT_EQ(retarget::boneFromName(retarget::boneName(static_cast<Bone>(b))), static_cast<Bone>(b)) << b;
  EXPECT_FALSE(retarget::boneFromName("Hips"));  // the canonical names are exact ("hips")
  EXPECT_EQ(behaviorKindFromName(toString(BehaviorKind::Gaze)), BehaviorKind::Gaze);
  EXPECT_FALSE(behaviorKindFromName("no such kind"));
  EXPECT_EQ(speech::visemeFromName(speech::visemeName(speech::Viseme::PP)), speech::Viseme::PP);
}
