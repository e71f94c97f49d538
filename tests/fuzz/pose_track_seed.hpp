// A valid recorded pose CSV (marionette_ar/pose_track.hpp) the fuzz target and the mutation test
// start from, written here: TRACKING, LIMITED and LOST rows as `marionette-ar track` writes
// them, one LOST row with numbers as truth.csv has, a CRLF line and a blank one.
#pragma once

namespace marionette::fuzz {

inline constexpr const char* kSeedPoseTrack =
    "frame,time,state,px,py,pz,qx,qy,qz,qw\n"
    "0,0.000000,TRACKING,0.1,0.62,0.57,-0.402746,0,0,0.915311\n"
    "1,0.033333,TRACKING,0.0066,0.6328,0.5713,-0.406088,0.005687,0.003197,0.913811\r\n"
    "2,0.066667,LIMITED,0.0133,0.641,0.5705,-0.40943,0.011373,0.006394,0.912262\n"
    "\n"
    "3,0.100000,LOST,,,,,,,\n"
    "5,0.166667,LOST,1e-3,2,-3.5,0,0,0,1\n"
    "6,0.200000,TRACKING,-0.25,0.5,+0.75,0.0,0.707107,0.0,0.707107\n";

// The same as track writes it since issue 40: with the pose's standard deviations (one row
// without: unknown).
inline constexpr const char* kSeedPoseTrackWithSigmas =
    "frame,time,state,px,py,pz,qx,qy,qz,qw,sigma_position_m,sigma_rotation_deg\n"
    "0,0.000000,TRACKING,0.1,0.62,0.57,-0.402746,0,0,0.915311,0.0012,0.081\n"
    "1,0.033333,LIMITED,0.0133,0.641,0.5705,-0.40943,0.011373,0.006394,0.912262,0.0071,0.52\r\n"
    "3,0.100000,LOST,,,,,,,,,\n"
    "6,0.200000,TRACKING,-0.25,0.5,+0.75,0.0,0.707107,0.0,0.707107,,\n";

}  // namespace marionette::fuzz
