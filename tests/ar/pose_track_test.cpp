// Recorded pose tracks (marionette_ar/pose_track.hpp): the CSV `marionette-ar track` writes,
// read back for a replayed camera. Rows by frame and by time, LOST rows, and bad files named
// by file, line and field. (Fuzz.PoseTracks mutates them.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <glm/gtc/quaternion.hpp>

#include "marionette_ar/pose_track.hpp"

using namespace marionette::ar;
using marionette::Diagnostics;

namespace {

constexpr const char* kHeader = "frame,time,state,px,py,pz,qx,qy,qz,qw\n";

std::string errorOf(const std::string& body) {
  Diagnostics d;
  const auto track = parsePoseTrack(body, "poses.csv", d);
  EXPECT_FALSE(track.has_value()) << body;
  EXPECT_FALSE(d.ok());
  return d.format();
}

}  // namespace

TEST(PoseTrack, ReadsWhatTrackWritesRowsByFrameAndTime) {
  // A camera 2 m up the +Z axis turned 90 deg about +Y (the quaternion of that), then a LOST
  // row as `track` writes it, then one as truth.csv writes it (numbers, still no pose).
  const double h = std::sqrt(0.5);
  const std::string text = std::string(kHeader) + "0,0.000000,TRACKING,0,0,2,0,0,0,1\r\n" +
                           "1,0.033333,LOST,,,,,,,\n\n" + "2,0.066667,LIMITED,1,2,3,0," + std::to_string(h) + ",0," +
                           std::to_string(h) + "\n" + "4,0.133333,LOST,1,2,3,0,0,0,1\n";
  Diagnostics d;
  const auto track = parsePoseTrack(text, "poses.csv", d);
  ASSERT_TRUE(track) << d.format();
  ASSERT_EQ(track->rows().size(), 4u);
  EXPECT_EQ(track->rows()[0].state, TrackingState::Tracking);
  EXPECT_EQ(glm::dvec3(track->rows()[0].cameraToWorld[3]), glm::dvec3(0, 0, 2));
  EXPECT_EQ(track->rows()[1].state, TrackingState::Lost);
  const RecordedPose* limited = track->atFrame(2);
  ASSERT_NE(limited, nullptr);
  EXPECT_EQ(limited->state, TrackingState::Limited);
  // 90 deg about +Y: the camera's -Z (its view) becomes world -X.
  const glm::dvec3 view = glm::dmat3(limited->cameraToWorld) * glm::dvec3(0, 0, -1);
  EXPECT_NEAR(view.x, -1, 1e-5);
  EXPECT_NEAR(view.z, 0, 1e-5);
  EXPECT_EQ(track->rows()[3].state, TrackingState::Lost);
  EXPECT_EQ(track->rows()[3].cameraToWorld, glm::dmat4(1.0));  // a LOST row has no pose
  EXPECT_EQ(track->atFrame(3), nullptr);                        // a frame the file skips
  EXPECT_EQ(track->atFrame(-1), nullptr);
  // By time: the row shown at a time, the rounded 0.066667 still frame 2's at exactly 2/30.
  EXPECT_EQ(track->atTime(-1).frame, 0);
  EXPECT_EQ(track->atTime(0.02).frame, 0);
  EXPECT_EQ(track->atTime(2.0 / 30.0).frame, 2);
  EXPECT_EQ(track->atTime(0.1).frame, 2);
  EXPECT_EQ(track->atTime(100).frame, 4);
}

// Since issue 40, track writes the pose's standard deviations too (empty when unknown).
TEST(PoseTrack, ReadsTheSigmaColumns) {
  const std::string text = "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg\n"
                           "0,0,TRACKING,0,0,2,0,0,0,1,0.0012,0.08\n"
                           "1,0.033333,LIMITED,0,0,2,0,0,0,1,,\n"
                           "2,0.066667,LOST,,,,,,,,,\n";
  Diagnostics d;
  const auto track = parsePoseTrack(text, "poses.csv", d);
  ASSERT_TRUE(track) << d.format();
  ASSERT_EQ(track->rows().size(), 3u);
  EXPECT_DOUBLE_EQ(track->rows()[0].positionSigmaM, 0.0012);
  EXPECT_DOUBLE_EQ(track->rows()[0].rotationSigmaDeg, 0.08);
  EXPECT_EQ(track->rows()[1].positionSigmaM, 0.0);  // unknown
  EXPECT_EQ(track->rows()[1].state, TrackingState::Limited);
  // A bad sigma is named; a row must have as many fields as the header.
  const std::string h = "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg\n";
  EXPECT_NE(errorOf(h + "0,0,TRACKING,0,0,2,0,0,0,1,-1,0\n").find("'sigma_position_m': not a number >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(h + "0,0,TRACKING,0,0,2,0,0,0,1,0,nan\n").find("'sigma_rotation_deg'"), std::string::npos);
  EXPECT_NE(errorOf(h + "0,0,TRACKING,0,0,2,0,0,0,1\n").find("10 fields, expected 12"), std::string::npos);
  EXPECT_NE(errorOf("frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m\n0,0,LOST,,,,,,,,\n").find("header"),
            std::string::npos);
}

TEST(PoseTrack, BadFilesNameTheFileLineAndField) {
  const std::string h = kHeader;
  struct Case {
    std::string body, expect;
  } cases[] = {
      {"", "empty: no header"},
      {h, "no rows after the header"},
      {"frame,time,state\n0,0,LOST\n", "header"},
      {h + "0,0,TRACKING,0,0,2,0,0,0\n", "9 fields"},
      {h + "0,0,TRACKING,0,0,2,0,0,0,1,7\n", "11 fields"},
      {h + "x,0,LOST,,,,,,,\n", "poses.csv:2: error: 'frame'"},
      {h + "-3,0,LOST,,,,,,,\n", "'frame'"},
      {h + "0,0,LOST,,,,,,,\n0,0.1,LOST,,,,,,,\n", "poses.csv:3: error: 'frame': 0 does not follow frame 0"},
      {h + "0,0.1,LOST,,,,,,,\n1,0.1,LOST,,,,,,,\n", "'time': not after"},
      {h + "0,nan,LOST,,,,,,,\n", "'time'"},
      {h + "0,-1,LOST,,,,,,,\n", "'time'"},
      {h + "0,0,tracking,0,0,2,0,0,0,1\n", "'state': 'tracking' is none of"},
      {h + "0,0,TRACKING,,,,,,,\n", "'px': missing (only a LOST row has no pose)"},
      {h + "0,0,TRACKING,0,0,2,0,0,0,\n", "'qw': missing"},
      {h + "0,0,TRACKING,0,inf,2,0,0,0,1\n", "'py': not a finite number"},
      {h + "0,0,TRACKING,0,0,2e9,0,0,0,1\n", "more than 1e6 m"},
      {h + "0,0,TRACKING,0,0,2,0,0,0,0.5\n", "norm 0.5"},
      {h + "0,0,TRACKING,0,0,2,0,0,0,1x\n", "'qw': not a finite number"},
      {h + "0,0,LOST,1,,,,,,\n", "'py': missing"},
      {h + std::string("0,0,LOST,,,\0,,,,\n", 18), "NUL byte"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.body);
    const std::string e = errorOf(c.body);
    EXPECT_NE(e.find("poses.csv"), std::string::npos) << e;
    EXPECT_NE(e.find(c.expect), std::string::npos) << e;
  }
  Diagnostics d;
  EXPECT_FALSE(readPoseTrack("/nonexistent/poses.csv", d));
  EXPECT_NE(d.format().find("/nonexistent/poses.csv: error: cannot read the pose CSV"), std::string::npos) << d.format();
}
