// Internal: JSON text with places. nlohmann keeps no source positions, so
// diagnostics about a value ("line 12:5: /bones/hips: no joint named ...") find
// it here by JSON pointer. Shared by the character-profile and joint-map readers.
#pragma once
#include <algorithm>
#include <cstddef>
#include <initializer_list>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "marionette/core/diagnostic.hpp"

namespace marionette::json_detail {

using Json = nlohmann::json;

// Byte offsets of the keys and values of a JSON text that nlohmann accepted, by
// JSON pointer ("/face/SMILE/0/amount"), so warnings can name line:column
// (nlohmann keeps no positions in its values). Also finds duplicate keys, which
// nlohmann resolves silently (the last one wins).
class JsonPlaces {
 public:
  explicit JsonPlaces(const std::string& text) {
    struct Frame {
      bool object = true;
      std::string pointer;
      std::size_t index = 0;
      bool expectKey = true;
      std::set<std::string> keys;
    };
    std::vector<Frame> stack;
    const std::size_t n = text.size();
    std::size_t i = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;  // nlohmann skips a BOM
    std::string pointer;  // of the value that starts next
    auto skipSpace = [&] {
      while (i < n && (text[i] == ' ' || text[i] == '\t' || text[i] == '\n' || text[i] == '\r')) ++i;
    };
    // Reads the string at text[i] (a quote); returns its decoded value.
    auto readString = [&]() -> std::string {
      const std::size_t start = i++;
      bool escaped = false;
      while (i < n && text[i] != '"') i += text[i] == '\\' ? (escaped = true, 2) : 1;
      i = std::min(i + 1, n);
      if (!escaped) return text.substr(start + 1, i - start - 2);
      try {  // rare: let nlohmann decode the escapes
        return Json::parse(text.substr(start, i - start)).get<std::string>();
      } catch (...) {
        return {};
      }
    };
    constexpr std::size_t kMaxDepth = 8;  // a profile is 4 deep; deeper nests are skipped, not recorded
    for (skipSpace(); i < n; skipSpace()) {
      if (!stack.empty()) {
        Frame& f = stack.back();
        const char c = text[i];
        if (c == (f.object ? '}' : ']')) {
          stack.pop_back();
          ++i;
          continue;
        }
        if (c == ',') {
          ++i;
          continue;
        }
        if (f.object && f.expectKey) {
          if (c != '"') return;  // not JSON after all
          const std::size_t at = i;
          const std::string key = readString();
          skipSpace();
          if (i < n && text[i] == ':') ++i;
          pointer = f.pointer + "/" + escape(key);
          if (stack.size() <= kMaxDepth) {
            if (!f.keys.insert(key).second) duplicates.emplace_back(pointer, at);
            keys_[pointer] = at;
          }
          f.expectKey = false;
          continue;
        }
        if (f.object) f.expectKey = true;
        else pointer = f.pointer + "/" + std::to_string(f.index++);
      }
      if (stack.size() <= kMaxDepth) values_[pointer] = i;
      const char c = text[i];
      if (c == '{' || c == '[') {
        Frame f;
        f.object = c == '{';
        if (stack.size() < kMaxDepth) f.pointer = pointer;
        stack.push_back(std::move(f));
        ++i;
      } else if (c == '"') {
        readString();
      } else {
        const std::size_t from = i;
        while (i < n && std::string_view(",]} \t\r\n").find(text[i]) == std::string_view::npos) ++i;
        if (i == from) return;  // a closing bracket where a value starts: not the JSON nlohmann read
      }
    }
  }
  static std::string escape(const std::string& key) {
    std::string out;
    for (char c : key) out += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
    return out;
  }
  [[nodiscard]] std::ptrdiff_t value(const std::string& pointer) const { return find(values_, pointer); }
  [[nodiscard]] std::ptrdiff_t key(const std::string& pointer) const { return find(keys_, pointer); }

  std::vector<std::pair<std::string, std::size_t>> duplicates;

 private:
  static std::ptrdiff_t find(const std::map<std::string, std::size_t>& m, const std::string& p) {
    auto it = m.find(p);
    return it == m.end() ? -1 : static_cast<std::ptrdiff_t>(it->second);
  }
  std::map<std::string, std::size_t> values_, keys_;
};

// Parses `text` (the contents of `path`) into `doc`; on a syntax error (or a number
// out of range) adds an error naming the file and line:column and returns false.
inline bool parseJsonText(const std::string& path, const std::string& text, Json& doc, Diagnostics& diags) {
  // JSON has no raw NUL (RFC 8259), and nlohmann stops reading at one, so what follows
  // would be ignored unchecked: the file is not JSON text (binary data, a wrong file).
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos) {
    const auto [line, col] = lineColumnAt(text, static_cast<std::ptrdiff_t>(nul));
    diags.error(path, "a NUL byte: not a JSON text file", line, col);
    return false;
  }
  try {  // load time: nlohmann reports the byte offset only through its exception
    doc = Json::parse(text);
    return true;
  } catch (const Json::parse_error& e) {
    const auto [line, col] = lineColumnAt(text, e.byte > 0 ? static_cast<std::ptrdiff_t>(e.byte) - 1 : 0);
    std::string msg = e.what();
    const auto pos = msg.find("syntax error");
    diags.error(path, pos != std::string::npos ? msg.substr(pos) : msg, line, col);
  } catch (const Json::exception& e) {
    // A number too large for a double ("number overflow parsing '1e999'"): place it by its text.
    std::string msg = e.what();
    const auto open = msg.find('\''), close = msg.rfind('\'');
    const auto at = open < close ? text.find(msg.substr(open + 1, close - open - 1)) : std::string::npos;
    const auto [line, col] = at == std::string::npos ? std::pair{0, 0} : lineColumnAt(text, static_cast<std::ptrdiff_t>(at));
    const auto pos = msg.find("] ");
    diags.error(path, pos != std::string::npos ? msg.substr(pos + 2) : msg, line, col);
  }
  return false;
}

// What both JSON readers (character profiles, joint maps) share: warnings placed
// at line:column by JSON pointer, duplicate and unknown keys, sections that must be
// objects. Derived readers add the meaning of the fields.
class JsonReaderBase {
 protected:
  // `sectionIgnored`: what happens to a section that is not an object ("ignored").
  JsonReaderBase(const std::string& file, const std::string& text, Diagnostics& d, const char* sectionIgnored)
      : file_(file), lines_(text), places_(text), diags_(d), sectionIgnored_(sectionIgnored) {
    for (const auto& [pointer, at] : places_.duplicates)
      warnAt(static_cast<std::ptrdiff_t>(at), pointer.substr(1) + ": duplicate key; the last one is used");
  }

  void warnAt(std::ptrdiff_t offset, const std::string& message) {
    const auto [line, column] = lines_.at(offset);
    diags_.warning(file_, message, line, column);
  }
  // A warning about the value at `pointer` (or its key), naming the field.
  void warn(const std::string& pointer, const std::string& message, bool atKey = false) {
    std::ptrdiff_t at = atKey ? places_.key(pointer) : places_.value(pointer);
    if (at < 0) at = places_.value(pointer);
    warnAt(at, pointer.substr(1) + ": " + message);
  }
  void unknownKeys(const Json& obj, const std::string& where, std::initializer_list<const char*> known) {
    if (!obj.is_object()) return;
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      const bool ok = std::any_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; });
      if (!ok) warn(where + "/" + JsonPlaces::escape(it.key()), "unknown key '" + it.key() + "' ignored", true);
    }
  }
  // The object at doc[key], or an empty object (with a warning when it is not one).
  const Json& section(const Json& doc, const char* key) {
    static const Json empty = Json::object();
    if (!doc.contains(key)) return empty;
    const Json& s = doc[key];
    if (s.is_object()) return s;
    warn(std::string("/") + key, std::string("expected an object; ") + sectionIgnored_);
    return empty;
  }

  const std::string& file_;
  LineIndex lines_;
  JsonPlaces places_;
  Diagnostics& diags_;

 private:
  const char* sectionIgnored_;
};

}  // namespace marionette::json_detail
