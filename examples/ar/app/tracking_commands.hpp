// marionette-ar's tracking commands (docs/tracking.md):
//   marionette-ar calibrate --board COLSxROWS --square M IMAGES... -o CAMERA.yml [--json]
//   marionette-ar track --camera CAMERA.yml --images PATTERN|FOLDER|IMAGE|VIDEO [--fps F]
//                       [--tracker markerless|apriltag] [--target IMAGE --target-width M]
//                       [--tag-size M] [--map MAP] [--save-map MAP] --poses OUT.csv [--json]
#pragma once

namespace marionette::ar {

// Runs `marionette-ar <command> ...` when argv[1] names a tracking command; returns the exit
// code, or -1 when argv[1] is not one of them.
int runTrackingCommand(int argc, char** argv);

}  // namespace marionette::ar
