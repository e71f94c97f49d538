// Chessboard calibration against opencv-doc's own result on the same images.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "marionette_ar/tracking/chessboard_calibration.hpp"
#include "test_data.hpp"

namespace {

using namespace marionette;
using namespace marionette::ar;

std::vector<std::string> leftImages() {
  std::vector<std::string> files;
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "left%02d.jpg", i);
    const std::string f = test::opencvData(name);
    if (i != 10) files.push_back(f);  // opencv-doc ships no left10.jpg
  }
  return files;
}

TEST(ChessboardCalibration, MatchesOpenCvDocsReferenceWithinTenPercent) {
  const std::vector<std::string> files = leftImages();
  for (const auto& f : files) MARIONETTE_REQUIRE_FILE(f);
  const std::string refFile = test::opencvData("left_intrinsics.yml");
  MARIONETTE_REQUIRE_FILE(refFile);
  Diagnostics d;
  const auto ref = readCameraModel(refFile, d);
  ASSERT_TRUE(ref) << d.format();
  const auto cal = calibrateChessboard(files, {.columns = 9, .rows = 6, .squareSize = 0.025}, d);
  ASSERT_TRUE(cal) << d.format();
  EXPECT_EQ(cal->usedImages.size(), 13u) << d.format();
  const double reference = 0.39259098975581364;  // avg_reprojection_error in left_intrinsics.yml
  std::printf("calibration rms %.4f px (reference %.4f), fx %.2f (%.2f), cx %.2f (%.2f), cy %.2f (%.2f)\n",
              cal->rmsReprojectionError, reference, cal->camera.fx, ref->fx, cal->camera.cx, ref->cx, cal->camera.cy,
              ref->cy);
  EXPECT_LT(std::abs(cal->rmsReprojectionError - reference), 0.1 * reference);
  EXPECT_NEAR(cal->camera.fx, ref->fx, 0.01 * ref->fx);
  EXPECT_EQ(cal->camera.fx, cal->camera.fy);
  EXPECT_NEAR(cal->camera.cx, ref->cx, 3.0);
  EXPECT_NEAR(cal->camera.cy, ref->cy, 3.0);
  EXPECT_NEAR(cal->camera.distortion[0], ref->distortion[0], 0.02);
  ASSERT_EQ(cal->perViewRms.size(), cal->usedImages.size());
  double sumSq = 0;
  for (double v : cal->perViewRms) sumSq += v * v;
  EXPECT_NEAR(std::sqrt(sumSq / static_cast<double>(cal->perViewRms.size())), cal->rmsReprojectionError, 1e-3);
}

TEST(ChessboardCalibration, BadInputIsAClearError) {
  Diagnostics d;
  EXPECT_FALSE(calibrateChessboard({}, {}, d));
  EXPECT_NE(d.format().find("at least 3 views"), std::string::npos) << d.format();
  Diagnostics d2;
  EXPECT_FALSE(calibrateChessboard({"/nonexistent.jpg"}, {}, d2));
  EXPECT_NE(d2.format().find("/nonexistent.jpg"), std::string::npos);
  Diagnostics d3;
  EXPECT_FALSE(calibrateChessboard(leftImages(), {.columns = 9, .rows = 6, .squareSize = std::nan("")}, d3));
  EXPECT_NE(d3.format().find("square"), std::string::npos);
  Diagnostics d4;
  EXPECT_FALSE(calibrateChessboard(leftImages(), {.columns = 1, .rows = 6}, d4));
  // A board that is not in the pictures: every image is skipped with a warning, then an error.
  Diagnostics d5;
  EXPECT_FALSE(calibrateChessboard(leftImages(), {.columns = 7, .rows = 7}, d5));
  EXPECT_NE(d5.format().find("found in 0 images"), std::string::npos) << d5.format();
  // Board images of two sizes: the second is named. left.jpg between them (612x459, no board)
  // is skipped and sets no size.
  const std::string larger = (std::filesystem::temp_directory_path() / "marionette_left02_800x600.png").string();
  cv::Mat grown;
  cv::resize(cv::imread(test::opencvData("left02.jpg"), cv::IMREAD_GRAYSCALE), grown, cv::Size(800, 600));
  ASSERT_TRUE(cv::imwrite(larger, grown));
  Diagnostics d6;
  EXPECT_FALSE(calibrateChessboard({test::opencvData("left01.jpg"), test::opencvData("left.jpg"), larger}, {}, d6));
  EXPECT_NE(d6.format().find(larger + ": error: is 800x600 but the first image with the board (" +
                             test::opencvData("left01.jpg") + ") is 640x480: one camera, one size"),
            std::string::npos)
      << d6.format();
}

// `left*.jpg` (the README's line) takes left.jpg first: 612x459 and no board. It is skipped and
// its size is not the calibration's: the size comes from the first image with the board.
TEST(ChessboardCalibration, AnImageWithoutTheBoardSetsNoSize) {
  std::vector<std::string> files = leftImages();
  files.insert(files.begin(), test::opencvData("left.jpg"));
  for (const auto& f : files) MARIONETTE_REQUIRE_FILE(f);
  Diagnostics d;
  const auto cal = calibrateChessboard(files, {.columns = 9, .rows = 6, .squareSize = 0.025}, d);
  ASSERT_TRUE(cal) << d.format();
  EXPECT_EQ(cal->usedImages.size(), 13u);
  ASSERT_EQ(cal->rejectedImages.size(), 1u);
  EXPECT_EQ(cal->rejectedImages[0], files[0]);
  EXPECT_NE(d.format().find(files[0] + ": warning: no 9x6 chessboard found: image skipped"), std::string::npos)
      << d.format();
  EXPECT_EQ(cal->camera.width, 640);
  EXPECT_EQ(cal->camera.height, 480);
}

}  // namespace
