// The tables of a generated report: printf-style cells, CSV files written row by row, Markdown
// text with its tables. Private to `marionette prt report` (report_tables.cpp).
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace marionette::cli::detail {

// printf into a std::string.
__attribute__((format(printf, 1, 2))) std::string str(const char* format, ...);

// A CSV file written row by row; numbers are formatted by the caller.
class Csv {
 public:
  Csv(const std::filesystem::path& path, const std::string& header) : out_(path) { out_ << header << '\n'; }
  void row(const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) out_ << (i ? "," : "") << cells[i];
    out_ << '\n';
  }
  [[nodiscard]] bool ok() const { return static_cast<bool>(out_); }

 private:
  std::ofstream out_;
};

struct Markdown {
  std::string text;
  void line(const std::string& s = "") { text += s + "\n"; }
  static std::string cell(const std::string& text) {  // a '|' inside a cell must be escaped
    std::string out;
    for (char ch : text) out += ch == '|' ? std::string("\\|") : std::string(1, ch);
    return out;
  }
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
    std::string h = "|", sep = "|";
    for (const auto& c : header) h += " " + cell(c) + " |", sep += "---|";
    line(h);
    line(sep);
    for (const auto& r : rows) {
      std::string s = "|";
      for (const auto& c : r) s += " " + cell(c) + " |";
      line(s);
    }
    line();
  }
};

}  // namespace marionette::cli::detail
