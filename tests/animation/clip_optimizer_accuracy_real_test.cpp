// Error of the load-time clip optimizer on real clips, in the ACL style: the
// distance, in model space, between virtual vertices rigidly attached to each
// joint (10 cm along each local axis, and the joint itself) when posed by the
// authored clip and by the optimized clip, over every 1/120 s of the clip.
// Writes a CSV (clip, keys, error) that docs/accuracy.md reports.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "marionette/animation/clip_optimizer.hpp"
#include "marionette/io/import.hpp"
#include "pose_error.hpp"
#include "test_data.hpp"

using namespace marionette;
using namespace marionette::test;


TEST(ClipOptimizerAccuracy, RealClipsStayWithinATenthOfAMillimetre) {
  const std::vector<std::string> files = accuracyClipFiles();
  std::ofstream csv(::testing::TempDir() + "clip_optimizer_error.csv");
  csv << "file,clip,keys_before,keys_after,max_error_m,p99_error_m\n";
  std::size_t totalBefore = 0, totalAfter = 0, pabBefore = 0, pabAfter = 0;
  float worst = 0.0f;
  for (const std::string& f : files) {
    MARIONETTE_REQUIRE_FILE(sharedAsset(f));
    ImportResult r = importAccuracyClips(sharedAsset(f));
    ASSERT_TRUE(r.ok()) << r.diagnostics.format();
    for (const Clip& authored : r.asset->clips) {
      Clip optimized = authored;
      ClipOptimizeStats st = optimizeClip(optimized, r.asset->skeleton);
      PoseErrors e;
      accumulateVirtualVertexErrors(r.asset->skeleton, authored, optimized, e);
      totalBefore += st.keysBefore;
      totalAfter += st.keysAfter;
      if (f.find("pab_") != std::string::npos) {
        pabBefore += st.keysBefore;
        pabAfter += st.keysAfter;
      }
      csv << f << ',' << authored.name << ',' << st.keysBefore << ',' << st.keysAfter << ',' << e.max << ','
          << e.percentile(0.99) << '\n';
      EXPECT_LT(e.max, 1e-4f) << f << " " << authored.name;  // goal: 0.1 mm at 10 cm from any joint
      worst = std::max(worst, e.max);
    }
  }
  std::printf("clip optimizer: worst error %.1f um\n", 1e6 * static_cast<double>(worst));
  // regression: docs/accuracy.md ("Load-time clip optimizer") publishes 16 um as the largest; 1.5x.
  EXPECT_LT(worst, 24e-6f);
  // The optimization does something on sampled FBX exports (Pab: T, R, S on every joint).
#ifdef MARIONETTE_HAS_ASSIMP
  EXPECT_LT(pabAfter, pabBefore / 3);
#endif
  EXPECT_LT(totalAfter, totalBefore);
  std::printf("clip optimizer: %zu keys -> %zu keys; CSV in %sclip_optimizer_error.csv\n", totalBefore, totalAfter,
              ::testing::TempDir().c_str());
}
