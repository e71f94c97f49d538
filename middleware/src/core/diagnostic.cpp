#include "marionette/core/diagnostic.hpp"

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

}  // namespace marionette
