// marionette-ar's tracking commands as a user runs them: calibrate on opencv-doc's
// chessboards, track an AprilTag on ViSP's benchmark image, and the errors a wrong camera,
// a damaged map or a missing option give.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "cli_run.hpp"
#include "test_data.hpp"

namespace marionette::test {
namespace {

namespace fs = std::filesystem;

CliRun runAr(const std::string& args) { return runCommand(::marionette::test::programPath("marionette-ar") + " " + args); }

double jsonNumber(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\"" + key + "\": ");
  return at == std::string::npos ? std::nan("") : std::atof(text.c_str() + at + key.size() + 4);
}

TEST(TrackingCli, CalibrateWritesACameraWithinTenPercentOfTheReference) {
  std::string images;
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[32];
    std::snprintf(name, sizeof name, "left%02d.jpg", i);
    MARIONETTE_REQUIRE_FILE(opencvData(name));
    images += " " + opencvData(name);
  }
  const fs::path out = fs::temp_directory_path() / "marionette_cli_camera.yml";
  fs::remove(out);
  const CliRun r = runAr("calibrate --board 9x6 --square 0.025" + images + " -o " + out.string() + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "views"), 13) << r.out;
  EXPECT_NEAR(jsonNumber(r.out, "rms_px"), 0.3926, 0.1 * 0.3926) << r.out;
  ASSERT_TRUE(fs::exists(out));
  // The file is OpenCV calibration YAML the tracker reads back.
  const CliRun again = runAr("track --camera " + out.string() + " --images /nonexistent --target " +
                             opencvData("graf1.png") + " --target-width 0.3 --poses /dev/null");
  EXPECT_EQ(again.status, 2);
  EXPECT_EQ(again.out.find(out.string()), std::string::npos) << "the camera file was accepted: " << again.out;
  EXPECT_NE(again.out.find("/nonexistent"), std::string::npos) << again.out;
}

// The README's calibrate line as written, on opencv-doc's folder: left*.jpg also takes left.jpg
// (another camera's 612x459 photo, no board), which is skipped with a warning.
TEST(TrackingCli, CalibrateTakesTheReadmesGlob) {
  MARIONETTE_REQUIRE_FILE(opencvData("left.jpg"));
  const fs::path out = fs::temp_directory_path() / "marionette_cli_glob_camera.yml";
  fs::remove(out);
  const CliRun r = runAr("calibrate --board 9x6 --square 0.025 " + opencvData("left") + "*.jpg -o " + out.string() +
                         " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "views"), 13) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "rejected"), 1) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "width"), 640) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "height"), 480) << r.out;
  EXPECT_NE(r.out.find(opencvData("left.jpg") + ": warning: no 9x6 chessboard found"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out));
}

TEST(TrackingCli, TracksAnAprilTagAndWritesTheCsv) {
  const std::string image = vispImage("AprilTag/benchmark/640x480/tag36_11_640x480.png");
  MARIONETTE_REQUIRE_FILE(image);
  const fs::path dir = fs::temp_directory_path() / "marionette_cli_apriltag";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  const cv::Mat frame = cv::imread(image, cv::IMREAD_COLOR);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(cv::imwrite((dir / "frames" / ("f" + std::to_string(i) + ".png")).string(), frame));
  std::ofstream(dir / "camera.yml") << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                       "   data: [ 700., 0., 319.5, 0., 700., 239.5, 0., 0., 1. ]\n";
  const CliRun r = runAr("track --camera " + (dir / "camera.yml").string() + " --images " + (dir / "frames").string() +
                         " --tracker apriltag --tag-size 0.2 --poses " + (dir / "poses.csv").string() + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "frames"), 3) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "tracked"), 3) << r.out;
  EXPECT_GT(jsonNumber(r.out, "ms_per_frame_median"), 0) << r.out;
  std::ifstream csv(dir / "poses.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg");
  ASSERT_TRUE(std::getline(csv, line));
  std::istringstream fields(line);
  std::vector<std::string> f;
  for (std::string v; std::getline(fields, v, ',');) f.push_back(v);
  ASSERT_EQ(f.size(), 11u) << line;  // the AprilTag tracker gives no sigmas: the last two are empty
  EXPECT_EQ(line.substr(line.size() - 2), ",,") << line;
  EXPECT_EQ(f[2], "TRACKING");
  // Tag 0 (the lowest id) is 2.013 m from the camera in ViSP's ground truth (cMo_0.txt).
  const double distance = std::hypot(std::atof(f[3].c_str()), std::atof(f[4].c_str()), std::atof(f[5].c_str()));
  EXPECT_NEAR(distance, 2.0134, 0.02 * 2.0134) << line;
  const double qn = std::hypot(std::hypot(std::atof(f[6].c_str()), std::atof(f[7].c_str())),
                               std::hypot(std::atof(f[8].c_str()), std::atof(f[9].c_str())));
  EXPECT_NEAR(qn, 1.0, 1e-6);
}

// --images names one image file: a sequence of one frame.
TEST(TrackingCli, TracksASingleImageFile) {
  const std::string image = vispImage("AprilTag/benchmark/640x480/tag36_11_640x480.png");
  MARIONETTE_REQUIRE_FILE(image);
  const fs::path dir = fs::temp_directory_path() / "marionette_cli_one_image";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "camera.yml") << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                       "   data: [ 700., 0., 319.5, 0., 700., 239.5, 0., 0., 1. ]\n";
  const CliRun r = runAr("track --camera " + (dir / "camera.yml").string() + " --images " + image +
                         " --tracker apriltag --tag-size 0.2 --poses " + (dir / "poses.csv").string() + " --json");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "frames"), 1) << r.out;
  EXPECT_EQ(jsonNumber(r.out, "tracked"), 1) << r.out;
  std::ifstream csv(dir / "poses.csv");
  std::string header, line;
  std::getline(csv, header);
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line.rfind("0,0.000000,TRACKING,", 0), 0u) << line;
  EXPECT_FALSE(std::getline(csv, line)) << "a second row: " << line;
}

// A stray image in the frames folder (the target's photo, another size) is named with its size
// and the frames', though it sorts before them.
TEST(TrackingCli, AStrayImageInTheFramesFolderIsNamed) {
  MARIONETTE_REQUIRE_FILE(opencvData("graf1.png"));
  const fs::path dir = fs::temp_directory_path() / "marionette_cli_stray_image";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(cv::imwrite((dir / "frames" / ("view_" + std::to_string(i) + ".png")).string(),
                            cv::Mat(240, 320, CV_8UC3, cv::Scalar(9, 9, 9))));
  fs::copy_file(opencvData("graf1.png"), dir / "frames" / "target.png");
  std::ofstream(dir / "camera.yml") << "%YAML:1.0\n---\nimage_width: 320\nimage_height: 240\n"
                                       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                       "   data: [ 300., 0., 159.5, 0., 300., 119.5, 0., 0., 1. ]\n";
  const CliRun r = runAr("track --camera " + (dir / "camera.yml").string() + " --images " + (dir / "frames").string() +
                         " --target " + opencvData("graf1.png") + " --target-width 0.3 --poses " +
                         (dir / "p.csv").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find((dir / "frames" / "target.png").string() +
                       ": error: image is 800x640 but the sequence's frames are 320x240"),
            std::string::npos)
      << r.out;
}

// A map of graf1.png over frames of another target relocalizes nothing: after 30 frames without
// a pose `track` says so on stderr and in --json's "warning", and still exits 0. Over graf1's
// own frames it says nothing.
TEST(TrackingCli, AMapOfAnotherTargetIsWarnedAbout) {
  MARIONETTE_REQUIRE_FILE(opencvData("graf1.png"));
  MARIONETTE_REQUIRE_FILE(opencvData("baboon.jpg"));
  const fs::path dir = fs::temp_directory_path() / "marionette_cli_foreign_map";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string camera = sourceFile("assets/cameras/synthetic_640x480.yml");
  auto sequence = [&](const std::string& target, const std::string& name) {
    const fs::path out = dir / name;
    const CliRun r = runCommand(programPath("marionette_write_sequence") + " --target " + opencvData(target) +
                                " --target-width 0.3 --camera " + camera + " --scenario orbit --frames 40 --out " +
                                out.string());
    EXPECT_EQ(r.status, 0) << r.out;
    return out.string();
  };
  const std::string graf = sequence("graf1.png", "graf"), baboon = sequence("baboon.jpg", "baboon");
  const std::string map = (dir / "graf.map").string();
  const CliRun made = runAr("track --camera " + camera + " --images " + graf + " --target " + opencvData("graf1.png") +
                            " --target-width 0.3 --poses " + (dir / "made.csv").string() + " --save-map " + map);
  ASSERT_EQ(made.status, 0) << made.out;

  // stdout (the JSON) to a file, stderr in `out`.
  struct Run {
    CliRun r;
    std::string json;
  };
  auto track = [&](const std::string& frames, const std::string& name) {
    const fs::path json = dir / (name + ".json");
    Run run{runCommand("( " + programPath("marionette-ar") + " track --camera " + camera + " --images " + frames +
                       " --map " + map + " --poses " + (dir / (name + ".csv")).string() + " --json > " + json.string() +
                       " )"),
            ""};
    run.json = readFile(json.string());
    return run;
  };
  const std::string says = "no frame matched the map's keyframes in 30 frames: is this the map of this target?";
  const Run foreign = track(baboon, "baboon");
  EXPECT_EQ(foreign.r.status, 0) << foreign.r.out;  // a warning, not an error
  EXPECT_EQ(jsonNumber(foreign.json, "tracked") + jsonNumber(foreign.json, "limited"), 0) << foreign.json;
  EXPECT_NE(foreign.r.out.find("marionette-ar track: warning: " + map + ": " + says), std::string::npos)
      << foreign.r.out;
  EXPECT_NE(foreign.json.find("\"warning\": \"" + map + ": " + says + "\""), std::string::npos) << foreign.json;

  const Run own = track(graf, "graf");
  EXPECT_EQ(own.r.status, 0) << own.r.out;
  EXPECT_GT(jsonNumber(own.json, "tracked"), 30) << own.json;
  EXPECT_EQ(own.r.out.find("warning"), std::string::npos) << own.r.out;
  EXPECT_NE(own.json.find("\"warning\": null"), std::string::npos) << own.json;
}

TEST(TrackingCli, BadInputIsNamed) {
  const fs::path dir = fs::temp_directory_path() / "marionette_cli_tracking_bad";
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  ASSERT_TRUE(cv::imwrite((dir / "frames" / "a.png").string(), cv::Mat(240, 320, CV_8UC3, cv::Scalar(9, 9, 9))));
  std::ofstream(dir / "camera.yml") << "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                       "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                       "   data: [ 600., 0., 319.5, 0., 600., 239.5, 0., 0., 1. ]\n";
  const std::string camera = (dir / "camera.yml").string(), frames = (dir / "frames").string();
  // Frames of another size than the calibration.
  CliRun r = runAr("track --camera " + camera + " --images " + frames + " --target " + opencvData("graf1.png") +
                   " --target-width 0.3 --poses " + (dir / "p.csv").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("320x240"), std::string::npos) << r.out;
  // A damaged map.
  std::ofstream(dir / "bad.map") << "MNPLANAR and then nothing useful";
  r = runAr("track --camera " + camera + " --images " + frames + " --map " + (dir / "bad.map").string() +
            " --poses " + (dir / "p.csv").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find((dir / "bad.map").string()), std::string::npos) << r.out;
  // The markerless tracker without a target or a map; a target without its width.
  r = runAr("track --camera " + camera + " --images " + frames + " --poses " + (dir / "p.csv").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--target"), std::string::npos) << r.out;
  r = runAr("track --camera " + camera + " --images " + frames + " --target " + opencvData("graf1.png") + " --poses " +
            (dir / "p.csv").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("--target-width"), std::string::npos) << r.out;
  r = runAr("track --camera " + camera + " --images " + frames + " --tracker sonar --poses x.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("sonar"), std::string::npos) << r.out;
  r = runAr("calibrate --board 9 -o x.yml a.jpg");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("COLSxROWS"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace marionette::test
