#include "marionette/core/diagnostic.hpp"

#include <algorithm>

namespace marionette {

std::string Diagnostic::format() const {
  std::string out;
  if (!file.empty()) {
    out += file;
    if (line > 0) {
      out += ':' + std::to_string(line);
      if (column > 0) out += ':' + std::to_string(column);
    }
    out += ": ";
  }
  switch (severity) {
    case Severity::Note: out += "note: "; break;
    case Severity::Warning: out += "warning: "; break;
    case Severity::Error: out += "error: "; break;
  }
  out += message;
  return out;
}

void Diagnostics::error(std::string file, std::string message, int line, int column) {
  items.push_back({Severity::Error, std::move(file), line, column, std::move(message)});
}

void Diagnostics::warning(std::string file, std::string message, int line, int column) {
  items.push_back({Severity::Warning, std::move(file), line, column, std::move(message)});
}

bool Diagnostics::ok() const noexcept {
  for (const auto& d : items)
    if (d.severity == Severity::Error) return false;
  return true;
}

bool Diagnostics::hasWarnings() const noexcept {
  for (const auto& d : items)
    if (d.severity == Severity::Warning) return true;
  return false;
}

std::string Diagnostics::format() const {
  std::string out;
  for (const auto& d : items) out += d.format() + '\n';
  return out;
}

std::pair<int, int> lineColumnAt(std::string_view text, std::ptrdiff_t offset) noexcept {
  if (offset < 0) return {0, 0};
  int line = 1, column = 1;
  const auto end = std::min(static_cast<std::size_t>(offset), text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {line, column};
}

LineIndex::LineIndex(std::string_view text) : size_(text.size()) {
  lineStarts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lineStarts_.push_back(i + 1);
}

std::pair<int, int> LineIndex::at(std::ptrdiff_t offset) const noexcept {
  if (offset < 0) return {0, 0};
  const std::size_t o = std::min(static_cast<std::size_t>(offset), size_);
  const auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), o) - 1;
  return {static_cast<int>(it - lineStarts_.begin()) + 1, static_cast<int>(o - *it) + 1};
}

}  // namespace marionette
