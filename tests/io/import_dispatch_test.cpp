// importAsset's choice of reader by extension: the project's own files and media are
// refused with the file named, never read by Assimp as a one-node "character".
#include <gtest/gtest.h>

#include <fstream>

#include "marionette/io/import.hpp"

using namespace marionette;

TEST(ImportDispatch, OurOwnFilesAndMediaAreNotCharacters) {
  const std::string dir = ::testing::TempDir();
  for (const char* name : {"map.json", "PROFILE.JSON", "speech.wav", "probe.hdr", "notes.txt", "block.bml"}) {
    const std::string path = dir + name;
    std::ofstream(path) << "{\"bones\": {\"hips\": \"Hips\"}}";
    const ImportResult r = importAsset(path);
    EXPECT_FALSE(r.ok()) << name;
    EXPECT_FALSE(r.asset.has_value()) << name;
    const std::string message = r.diagnostics.format();
    EXPECT_NE(message.find(path + ": error: a '."), std::string::npos) << message;
    EXPECT_NE(message.find("is not a character or motion"), std::string::npos) << message;
  }
  // A JSON file says what it may be instead.
  const ImportResult json = importAsset(dir + "map.json");
  EXPECT_NE(json.diagnostics.format().find("a joint map, profile or scene file?"), std::string::npos);
}
