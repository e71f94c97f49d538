// printf-style cells for the report's tables (report_tables.hpp).
#include "report_tables.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <string>

namespace marionette::cli::detail {

std::string str(const char* format, ...) {
  va_list args, copy;
  va_start(args, format);
  va_copy(copy, args);
  const int size = std::vsnprintf(nullptr, 0, format, copy);
  va_end(copy);
  std::string out(static_cast<std::size_t>(std::max(size, 0)) + 1, '\0');
  std::vsnprintf(out.data(), out.size(), format, args);
  va_end(args);
  out.pop_back();
  return out;
}

}  // namespace marionette::cli::detail
