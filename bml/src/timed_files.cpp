#include "marionette/core/text_file.hpp"
#include "marionette/bml/timed_files.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace marionette::bml {

TimedFiles::TimedFiles(Realizer& realizer, std::vector<TimedFile> files)
    : realizer_(realizer), files_(std::move(files)) {
  std::stable_sort(files_.begin(), files_.end(), [](const TimedFile& a, const TimedFile& b) { return a.time < b.time; });
}

void TimedFiles::sendDue(double now, const std::function<void(const Diagnostic&)>& report) {
  for (; next_ < files_.size() && files_[next_].time <= now + 1e-9; ++next_) {
    const TimedFile& f = files_[next_];
    std::string text = f.text.value_or(std::string());
    Diagnostics unread;
    if (!f.text && !readTextFile(f.path, text, unread, "cannot read the BML file")) {
      for (const Diagnostic& d : unread.items) report(d);
      continue;
    }
    SchedulerOptions options;  // the file's own folder holds what it names (<bmlt:audiofile fileName>)
    options.fileDirectory = std::filesystem::path(f.path).parent_path().generic_string();
    const Schedule s = realizer_.perform(text, f.character, options, f.time);
    for (const Warning& w : s.warnings)
      report(Diagnostic{w.fatal ? Severity::Error : Severity::Warning, f.path, w.line, w.column,
                        std::string(toString(w.type)) + ": " +
                            (w.behaviorId.empty() ? "" : "behavior '" + w.behaviorId + "': ") + w.message});
  }
}

void useSceneDialects(Realizer& realizer, const SceneLoadResult& loaded) {
  for (const auto& [character, name] : loaded.bmlDialects)
    if (const std::optional<Dialect> d = dialectFromName(name)) realizer.setDialect(character, *d);
}

}  // namespace marionette::bml
