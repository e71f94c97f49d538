// The JSON reading the authoring files share (augmentation.cpp, authoring_actions.cpp): every
// problem names the file and the key, unknown keys are warnings, numbers are range-checked.
#pragma once
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "marionette/core/diagnostic.hpp"

namespace marionette::ar::detail {

using Json = nlohmann::json;

constexpr double kMaxCoordinate = 1e4;  // metres or pixels: past this a value is a typo, not a scene

class Reader {
 public:
  Reader(const std::string& path, Diagnostics& d) : path_(path), d_(d) {}
  void error(const std::string& key, const std::string& message) { d_.error(path_, "'" + key + "': " + message); }
  void warning(const std::string& key, const std::string& message) { d_.warning(path_, "'" + key + "': " + message); }
  [[nodiscard]] std::string resolve(const std::string& p) const {
    if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
    return (std::filesystem::path(path_).parent_path() / p).lexically_normal().string();
  }

  // Unknown keys are said, never dropped silently (a misspelt "scael" would otherwise vanish).
  void onlyKeys(const Json& obj, const std::string& where, std::initializer_list<const char*> keys) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool known = false;
      for (const char* k : keys) known = known || it.key() == k;
      if (!known) warning(where.empty() ? it.key() : where + "." + it.key(), "unknown key, ignored");
    }
  }

  bool string(const Json& obj, const char* key, const std::string& where, bool required, std::string& out) {
    const std::string name = where.empty() ? key : where + "." + key;
    if (!obj.contains(key)) {
      if (required) error(name, "missing");
      return !required;
    }
    if (!obj[key].is_string() || obj[key].get<std::string>().empty()) {
      error(name, "expected a non-empty string");
      return false;
    }
    out = obj[key].get<std::string>();
    return true;
  }

  bool number(const Json& obj, const char* key, const std::string& where, bool required, double lo, double hi,
              double& out) {
    const std::string name = where.empty() ? key : where + "." + key;
    if (!obj.contains(key)) {
      if (required) error(name, "missing");
      return !required;
    }
    const Json& v = obj[key];
    if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < lo || v.get<double>() > hi) {
      error(name, "expected a number in [" + trim(lo) + ", " + trim(hi) + "]");
      return false;
    }
    out = v.get<double>();
    return true;
  }

  // n finite numbers, each stored as a float: the writer wrote floats, so this is exact.
  // Optional ones keep `out` when absent.
  bool floats(const Json& obj, const char* key, const std::string& where, std::size_t n, float* out,
              bool required = true) {
    const std::string name = where + "." + key;
    if (!obj.contains(key)) {
      if (required) error(name, "missing");
      return !required;
    }
    const Json& v = obj[key];
    bool ok = v.is_array() && v.size() == n;
    for (std::size_t i = 0; ok && i < n; ++i)
      ok = v[i].is_number() && std::isfinite(v[i].get<double>()) && std::abs(v[i].get<double>()) <= kMaxCoordinate;
    if (!ok) {
      error(name, "expected " + std::to_string(n) + " finite numbers (at most " + trim(kMaxCoordinate) + " in size)");
      return false;
    }
    for (std::size_t i = 0; i < n; ++i) out[i] = v[i].get<float>();
    return true;
  }

  // The text as a JSON object with "format" and "version" as expected: what both file kinds start
  // with. nullopt after an error naming the file (not JSON, not an object, another format, a
  // newer version); `what` says what the file should be ("an augmentation").
  std::optional<Json> document(const std::string& text, const char* what, const char* format, int version) {
    Json root;
    try {
      root = Json::parse(text);
    } catch (const Json::exception& e) {  // parse_error, and out_of_range for a number like 1e999
      d_.error(path_, std::string("not JSON: ") + e.what());
      return std::nullopt;
    }
    if (!root.is_object()) {
      d_.error(path_, std::string(what) + " is a JSON object");
      return std::nullopt;
    }
    std::string f;
    if (!string(root, "format", "", true, f)) return std::nullopt;
    if (f != format) {
      error("format", "expected \"" + std::string(format) + "\", not \"" + f + "\"");
      return std::nullopt;
    }
    double v = 0;
    if (!number(root, "version", "", true, 1, 1e6, v)) return std::nullopt;
    if (v != version) {
      error("version", "version " + std::to_string(static_cast<long long>(v)) +
                           " was written by a newer marionette; this one reads version " + std::to_string(version));
      return std::nullopt;
    }
    return root;
  }

 private:
  static std::string trim(double v) {
    std::string s = std::to_string(v);
    while (s.find('.') != std::string::npos && (s.back() == '0' || s.back() == '.')) {
      const bool dot = s.back() == '.';
      s.pop_back();
      if (dot) break;
    }
    return s;
  }
  std::string path_;
  Diagnostics& d_;
};

}  // namespace marionette::ar::detail
