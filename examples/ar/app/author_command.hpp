// marionette-ar author SCENE.json --actions ACTIONS.json -o AUGMENTATION.json [--json]: an
// authoring session replayed headless over the scene's recorded camera sequence (docs/authoring.md).
#pragma once

namespace marionette::ar {

// argv[1] is "author"; returns the exit code (0, or 2 with an error naming the file and the action).
int runAuthorCommand(int argc, char** argv);

}  // namespace marionette::ar
