// marionette-ar: the reference AR renderer. Embeds the middleware as an engine
// would (scene, BML realizer, the bridge's palettes) and draws its characters,
// skinned and lit by the environment, over a camera background.
//
//   marionette-ar SCENE.json [--headless] [--frames N] [--out DIR] [--screenshot FILE]
//                 [--exposure E] [--width W] [--height H] [--hide-characters] [--audio-dir DIR]
//                 [--prt shadowed|unshadowed|off] [--prt-bands N] [--prt-rays R] [--prt-cache DIR]
//                 [--restore AUGMENTATION.json [--truth CSV]] [--json]
//   marionette-ar calibrate ... | track ...   (camera tracking: tracking_commands.hpp)
//   marionette-ar author SCENE.json --actions ACTIONS.json -o AUGMENTATION.json  (author_command.hpp)
//   marionette-ar [COMMAND] --help | --version   (ar_cli.hpp)
//
// Headless renders offscreen into DIR/frame_0000.png ... (still needs an X
// display: run it under xvfb-run; docs/ar-renderer.md).
#include <cstring>
#include <utility>

#include "ar_app.hpp"
#include "ar_cli.hpp"
#include "augmentation_restore.hpp"
#include "render_args.hpp"
#if MARIONETTE_AR_HAS_TRACKING
#include "author_command.hpp"
#include "tracking_commands.hpp"
#endif

int main(int argc, char** argv) {
  using namespace marionette::ar;
  (void)secondsSinceProcessStart();  // starts its clock
#if MARIONETTE_AR_HAS_TRACKING
  if (const int code = runTrackingCommand(argc, argv); code >= 0) return code;
  if (argc > 1 && std::strcmp(argv[1], "author") == 0) return runAuthorCommand(argc, argv);
#endif
  RenderArgs args;
  if (!parseRenderArgs(argc, argv, args)) return renderUsage();
  if (args.help) return renderUsage(stdout);
  if (args.version) return printVersion();

  ArApp app(std::move(args));
  if (const int code = app.setUp()) return code;
  int status = ArApp::kNextFrame;
  while (status == ArApp::kNextFrame && app.wantsFrame()) status = app.frame();
  return status > 0 ? status : app.finish();
}
