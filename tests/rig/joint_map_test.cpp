// loadJointMap on files that are not joint maps: an error naming the file, not an empty map.
#include <gtest/gtest.h>

#include <fstream>

#include "marionette/rig/joint_map.hpp"

using namespace marionette;

TEST(JointMapFile, ValidJsonOfAnotherKindIsAnError) {
  Asset asset;
  asset.skeleton.addJoint("Hips", -1, Transform{});
  const std::string path = ::testing::TempDir() + "joint_map_test_profile.json";
  std::ofstream(path) << "{\"idle\": \"Idle\", \"face\": {}}";
  const retarget::JointMapResult r = retarget::loadJointMap(path, asset);
  EXPECT_FALSE(r.diagnostics.ok());
  EXPECT_NE(r.diagnostics.format().find(path + ":1:1: error: not a joint map: it has neither \"bones\" nor \"chains\""),
            std::string::npos)
      << r.diagnostics.format();
  // A map with only chains is still a map.
  std::ofstream(path) << "{\"chains\": {\"spine\": []}}";
  const retarget::JointMapResult chains = retarget::loadJointMap(path, asset);
  EXPECT_EQ(chains.diagnostics.format().find("not a joint map"), std::string::npos) << chains.diagnostics.format();
}
