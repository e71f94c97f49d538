// A real asset loaded with its shipped profile (assets/profiles/), for the import
// tests. Failures are test failures naming the file; nullptr then.
#pragma once
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "marionette/io/import.hpp"
#include "marionette/rig/rig.hpp"
#include "test_data.hpp"

namespace marionette::test {

// `assetPath` is a full path; `profile` a file name in assets/profiles/.
inline std::shared_ptr<Rig> loadRigWithProfile(const std::string& assetPath, const std::string& profile) {
  ImportResult r = importAsset(assetPath);
  EXPECT_TRUE(r.ok()) << r.diagnostics.format();
  if (!r.ok()) return nullptr;
  auto a = std::make_shared<Asset>(std::move(*r.asset));
  auto rig = std::make_shared<Rig>(*a);
  CharacterProfileResult p = loadCharacterProfile(sourceFile("assets/profiles/" + profile), *a);
  EXPECT_TRUE(p.diagnostics.items.empty()) << p.diagnostics.format();
  rig->setProfile(std::move(p.profile));
  return rig;
}

// RobotExpressive with the profile guessed from the file, loaded once for the program
// (skeleton and clips only); nullptr when it cannot be read.
inline std::shared_ptr<const Rig> robotRig() {
  static const std::shared_ptr<const Rig> rig = [] {
    ImportOptions o;
    o.loadMeshes = false;
    ImportResult r = importAsset(sharedAsset("characters/RobotExpressive.glb"), o);
    return r.ok() ? std::make_shared<Rig>(*r.asset) : nullptr;
  }();
  return rig;
}

}  // namespace marionette::test
