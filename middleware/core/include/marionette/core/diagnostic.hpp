// Diagnostics for load and parse time: every error names the file (or BML block),
// the place (line:column, joint or track name) and what was expected.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace marionette {

enum class Severity { Note, Warning, Error };

struct Diagnostic {
  Severity severity = Severity::Error;
  std::string file;     // file path or BML block id; may be empty
  int line = 0;         // 1-based; 0 when unknown
  int column = 0;       // 1-based; 0 when unknown
  std::string message;  // what is wrong and what was expected

  // "file:line:col: error: message" (the place parts left out when unknown).
  [[nodiscard]] std::string format() const;
};

// A list of diagnostics collected while loading; `ok()` is false if any is an error.
struct Diagnostics {
  std::vector<Diagnostic> items;

  void error(std::string file, std::string message, int line = 0, int column = 0);
  void warning(std::string file, std::string message, int line = 0, int column = 0);
  [[nodiscard]] bool ok() const noexcept;
  [[nodiscard]] bool hasWarnings() const noexcept;
  [[nodiscard]] std::string format() const;  // one line per diagnostic
};

// 1-based line and column of a byte offset in text ({0, 0} for a negative offset).
// Scans from the start: for one place. For many places in one text, LineIndex.
[[nodiscard]] std::pair<int, int> lineColumnAt(std::string_view text, std::ptrdiff_t offset) noexcept;

// Line starts of a text, found once; then line and column of any offset in O(log lines).
class LineIndex {
 public:
  explicit LineIndex(std::string_view text);
  [[nodiscard]] std::pair<int, int> at(std::ptrdiff_t offset) const noexcept;

 private:
  std::vector<std::size_t> lineStarts_;
  std::size_t size_ = 0;
};

}  // namespace marionette
