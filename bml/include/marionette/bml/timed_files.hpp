// Sends BML files at scene times: a scene file's "bml" list (SceneLoadResult::bml)
// played back by whoever drives the realizer (the `marionette run` tool, the
// reference AR renderer). Reads each file when it is due (command time, not
// per frame) and reports problems as diagnostics naming the file, line and column.
#pragma once
#include <functional>
#include <vector>

#include "marionette/bml/realizer.hpp"
#include "marionette/core/diagnostic.hpp"
#include "marionette/scene_file/scene_file.hpp"

namespace marionette::bml {

class TimedFiles {
 public:
  TimedFiles(Realizer& realizer, std::vector<TimedFile> files);  // sorted by time, stable

  // Performs every file whose time is at most `now`, at its own time. Each
  // unreadable file and each BML warning goes to `report` (errors for fatal ones).
  void sendDue(double now, const std::function<void(const Diagnostic&)>& report);
  [[nodiscard]] bool done() const noexcept { return next_ >= files_.size(); }

 private:
  Realizer& realizer_;
  std::vector<TimedFile> files_;
  std::size_t next_ = 0;
};

// Gives each character of a loaded scene file its "bmlDialect" (SceneLoadResult::bmlDialects).
void useSceneDialects(Realizer& realizer, const SceneLoadResult& loaded);

}  // namespace marionette::bml
