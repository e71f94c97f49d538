#include "marionette_ar/tracking/camera_model.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string_view>

#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>

#include "marionette/core/limits.hpp"

namespace marionette::ar {

namespace {

constexpr int kMaxCameraSide = 65536;

bool finite(double v) { return std::isfinite(v); }

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Whether an !!opencv-matrix node has whole-number rows and cols in 1..maxSide. Checked
// before OpenCV reads the matrix: cv::read(FileNode, Mat) allocates rows x cols before it
// counts the data (a rows or cols that is not a number reads as INT_MAX: 8 GB asked for by
// one line of text), and without 'rows' copies 'sizes' into a 32-entry array on the stack
// whatever its length.
bool smallMatrix(const cv::FileNode& n, int maxSide) {
  for (const char* key : {"rows", "cols"}) {
    const cv::FileNode v = n[key];
    if (!(v.isInt() || v.isReal())) return false;
    const double d = v.real();
    if (!(d >= 1 && d <= maxSide) || d != std::floor(d)) return false;
  }
  return true;
}

// Whether text that does not start as OpenCV's formats do ("%YAML", "<?xml", "{") is YAML keys
// without the header, as calibrations written by hand often are: its first line that is not
// blank or a comment is a "---" or a "key:" at column 0.
bool headerlessYaml(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l = text.substr(at, end - at);
    at = end + 1;
    const std::size_t content = l.find_first_not_of(" \t\r");
    if (content == std::string_view::npos || l[content] == '#') continue;
    if (l.substr(0, 3) == "---") return true;
    std::size_t key = 0;
    while (key < l.size() && (std::isalnum(static_cast<unsigned char>(l[key])) || l[key] == '_')) ++key;
    return key > 0 && key < l.size() && l[key] == ':';
  }
  return false;
}

// What is wrong with the 'data' of an !!opencv-matrix whose rows and cols are checked, empty
// when nothing is. cv::read throws "readRawData can only be used to read plain sequences of
// numbers" for a word among them, and asserts on a missing 'data' or a count that is not
// rows x cols, naming neither the field nor the value.
std::string matrixDataProblem(const cv::FileNode& matrix) {
  const cv::FileNode data = matrix["data"];
  if (data.empty() || !data.isSeq()) return "'data' is missing or not a list of numbers";
  const std::size_t expected = static_cast<std::size_t>(matrix["rows"].real() * matrix["cols"].real());
  for (std::size_t i = 0; i < data.size(); ++i) {
    const cv::FileNode v = data[static_cast<int>(i)];
    if (v.isInt() || v.isReal()) continue;
    const std::string what = v.isString() ? "\"" + v.string() + "\""
                             : v.isSeq()  ? std::string("a list")
                             : v.isMap()  ? std::string("a map")
                                          : std::string("empty");
    return "data[" + std::to_string(i) + "] is " + what + ", not a number";
  }
  if (data.size() != expected)
    return "'data' has " + std::to_string(data.size()) + " numbers but rows x cols is " + std::to_string(expected);
  return {};
}

// OpenCV's YAML parser (4.6) loops forever, or reads stale bytes of its line buffer, when
// text follows the end of the first document: a "..." line then a line starting with '-',
// or a root collection that does not start at column 0 ("-----0" then a shorter line). A
// calibration is one document whose root is a map at column 0: anything else is refused
// before OpenCV sees it. "" when the YAML has that shape.
std::string yamlShapeProblem(const std::string& text) {
  bool directives = true, root = false;  // before the root's first line; inside the root
  int line = 0;
  for (std::size_t at = 0; at < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view l(text.data() + at, end - at);
    at = end + 1;
    const std::size_t content = l.find_first_not_of(" \r");
    if (content == std::string_view::npos || l[content] == '#') continue;  // blank or a comment
    auto where = [&] { return " (line " + std::to_string(line + 1) + ")"; };
    const bool marker = l.substr(0, 3) == "---" || l.substr(0, 3) == "...";
    if (!root) {
      if (l[0] == '%') continue;  // %YAML:1.0 and other directives
      if (directives && l.substr(0, 3) == "---") {
        directives = false;
        const std::size_t rest = l.find_first_not_of(" \r", 3);
        if (rest != std::string_view::npos && l[rest] != '#')
          return "the YAML has text after '---' on its line" + where() + ": a calibration's keys start on the next";
        continue;
      }
      if (marker) return "an empty YAML document" + where() + ": a calibration has one, with its keys";
      if (!(std::isalnum(static_cast<unsigned char>(l[0])) || l[0] == '_'))
        return "the YAML's first key" + where() + " is not at the start of its line: not a calibration's map";
      root = true;
    } else if (marker) {
      return "a second YAML document" + where() + ": a calibration has one";
    }
  }
  return {};
}

// What makes `text` unfit for OpenCV's FileStorage parsers (4.6), empty when nothing does.
// They read up to the first NUL byte, and the XML parser reads through a NULL pointer when
// the text ends inside a tag after an '=' ("<?xml v3=") or a NUL byte cuts it there. They
// recurse once per nesting level with no limit: 50,000 levels of [, { or <tag> (100 KB of
// text) overflow an 8 MiB stack. A calibration nests three levels; the count here takes
// every bracket and tag, in strings too, so it can only overstate.
constexpr int kMaxNesting = 64;
std::string textProblem(const std::string& text, bool yamlWithoutHeader) {
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos)
    return "a NUL byte at byte " + std::to_string(nul) + ": not a YAML, XML or JSON text file";
  // Base64 blocks (YAML "!!binary", JSON "$base64$", XML type_id="binary"): OpenCV writes
  // them only when asked to (FileStorage::BASE64), and loops forever on a row of 60 'A's.
  for (const char* base64 : {"!!binary", "$base64$", "\"binary\"", "'binary'"})
    if (const std::size_t at = text.find(base64); at != std::string::npos)
      return std::string("base64 data (") + base64 + " at byte " + std::to_string(at) +
             "): write the calibration as text numbers";
  const std::size_t bom = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;  // OpenCV skips one, then looks
  if (text.compare(bom, 5, "%YAML") == 0 || yamlWithoutHeader) {
    if (std::string why = yamlShapeProblem(text.substr(bom)); !why.empty()) return why;
  } else if (text.compare(bom, 5, "<?xml") == 0) {
    if (text[text.find_last_not_of(" \t\r\n")] != '>')
      return "the XML ends inside a tag or before its last tag closes: truncated";
  }
  int depth = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i], next = i + 1 < text.size() ? text[i + 1] : '\0';
    if (ch == '[' || ch == '{' || (ch == '<' && next != '/' && next != '?' && next != '!')) {
      if (++depth > kMaxNesting)
        return "nested deeper than " + std::to_string(kMaxNesting) + " levels at byte " + std::to_string(i) +
               ": not a calibration (OpenCV's parser would run out of stack)";
    } else if (ch == ']' || ch == '}' || (ch == '<' && next == '/') || (ch == '/' && next == '>')) {
      depth = std::max(depth - 1, 0);
    }
  }
  return {};
}

}  // namespace

std::string CameraModel::problem() const {
  if (width < 1 || height < 1 || width > kMaxCameraSide || height > kMaxCameraSide)
    return "image size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1x1 .. 65536x65536";
  for (double v : {fx, fy, cx, cy})
    if (!finite(v)) return "camera matrix has a NaN or infinite value";
  for (double v : distortion)
    if (!finite(v)) return "distortion coefficients have a NaN or infinite value";
  if (!(fx > 0) || !(fy > 0)) return "focal length (fx " + num(fx) + ", fy " + num(fy) + ") is not positive";
  if (cx < 0 || cy < 0 || cx > width || cy > height)
    return "principal point (" + num(cx) + ", " + num(cy) + ") is outside the " + std::to_string(width) + "x" +
           std::to_string(height) + " image";
  for (double v : distortion)
    if (std::abs(v) > 100) return "distortion coefficient " + num(v) + " is beyond +-100";
  return {};
}

bool CameraModel::hasDistortion() const noexcept {
  for (double v : distortion)
    if (v != 0.0) return true;
  return false;
}

double CameraModel::fovYDegrees() const noexcept {
  return 2.0 * std::atan2(0.5 * height, fy) * 180.0 / 3.14159265358979323846;
}

glm::mat4 CameraModel::glProjection(float nearZ, float farZ) const noexcept {
  // x_ndc = (2 (fx X/Z' + cx) / w - 1) with Z' = -Z; y flips because pixel rows go down.
  glm::mat4 p(0.0f);
  p[0][0] = static_cast<float>(2.0 * fx / width);
  p[1][1] = static_cast<float>(2.0 * fy / height);
  p[2][0] = static_cast<float>(1.0 - 2.0 * (cx + 0.5) / width);
  p[2][1] = static_cast<float>(2.0 * (cy + 0.5) / height - 1.0);
  p[2][2] = -(farZ + nearZ) / (farZ - nearZ);
  p[2][3] = -1.0f;
  p[3][2] = -2.0f * farZ * nearZ / (farZ - nearZ);
  return p;
}

CameraModel CameraModel::scaledTo(int newWidth, int newHeight) const noexcept {
  CameraModel c = *this;
  const double sx = static_cast<double>(newWidth) / width, sy = static_cast<double>(newHeight) / height;
  c.width = newWidth;
  c.height = newHeight;
  // Pixel centres at integers: scale about the image corner (-0.5, -0.5).
  c.fx = fx * sx;
  c.fy = fy * sy;
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  return c;
}

std::optional<CameraModel> readCameraModel(const std::string& file, Diagnostics& diagnostics) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    diagnostics.error(file, "camera file does not exist or is not a file");
    return std::nullopt;
  }
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size > (1u << 20)) {
    diagnostics.error(file, "camera file is larger than 1 MiB: not a calibration");
    return std::nullopt;
  }
  // Read once, checked, and parsed from memory: OpenCV given the path would also gunzip a
  // ".gz" past the size limit and read bytes other than the ones checked.
  std::string text;
  {
    std::ifstream in(file, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (in.bad() || text.size() != size) {
      diagnostics.error(file, "camera file cannot be read");
      return std::nullopt;
    }
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) {
    diagnostics.error(file, "camera file is empty: not a calibration");
    return std::nullopt;
  }
  // OpenCV tells its formats by their first bytes and calls anything else "Unsupported file
  // storage format". YAML keys without "%YAML:1.0" are read as YAML 1.0 (the header is put
  // before them); other text is refused saying what is expected.
  const std::size_t bom = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  const bool known = text.compare(bom, 5, "%YAML") == 0 || text.compare(bom, 5, "<?xml") == 0 ||
                     text.compare(bom, 1, "{") == 0;
  const bool withoutHeader = !known && headerlessYaml(std::string_view(text).substr(bom));
  if (!known && !withoutHeader) {
    diagnostics.error(file, "not OpenCV calibration YAML, XML or JSON: YAML must start with %YAML:1.0 (or with "
                            "its keys, image_width: ...), XML with <?xml, JSON with {");
    return std::nullopt;
  }
  if (const std::string why = textProblem(text, withoutHeader); !why.empty()) {
    diagnostics.error(file, why);
    return std::nullopt;
  }
  if (withoutHeader) text = "%YAML:1.0\n" + text.substr(bom);
  CameraModel c;
  try {
    cv::FileStorage fs(text, cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_AUTO);
    if (!fs.isOpened()) {
      diagnostics.error(file, "OpenCV cannot read it as calibration YAML or XML");
      return std::nullopt;
    }
    auto integer = [&](const char* key, int& out) {
      const cv::FileNode n = fs[key];
      if (n.empty() || !(n.isInt() || n.isReal())) {
        diagnostics.error(file, std::string("'") + key + "' is missing or not a number");
        return false;
      }
      const double v = n.real();
      if (!(v >= 1 && v <= kMaxCameraSide) || v != std::floor(v)) {
        diagnostics.error(file, std::string("'") + key + "' " + num(v) + " is not a whole number in 1..65536");
        return false;
      }
      out = static_cast<int>(v);
      return true;
    };
    if (!integer("image_width", c.width) || !integer("image_height", c.height)) return std::nullopt;
    cv::Mat k, d;
    const cv::FileNode kn = fs["camera_matrix"], dn = fs["distortion_coefficients"];
    if (kn.empty() || !kn.isMap()) {
      diagnostics.error(file, "'camera_matrix' is missing or not an !!opencv-matrix");
      return std::nullopt;
    }
    if (!smallMatrix(kn, 3)) {
      diagnostics.error(file, "'camera_matrix' has no whole-number rows and cols of 1 to 3: not a 3x3 !!opencv-matrix");
      return std::nullopt;
    }
    if (const std::string why = matrixDataProblem(kn); !why.empty()) {
      diagnostics.error(file, "'camera_matrix': " + why);
      return std::nullopt;
    }
    kn >> k;
    if (k.rows != 3 || k.cols != 3 || k.channels() != 1) {
      diagnostics.error(file, "'camera_matrix' is " + std::to_string(k.rows) + "x" + std::to_string(k.cols) +
                                  ", not 3x3");
      return std::nullopt;
    }
    k.convertTo(k, CV_64F);
    if (k.at<double>(0, 1) != 0 || k.at<double>(1, 0) != 0 || k.at<double>(2, 0) != 0 || k.at<double>(2, 1) != 0 ||
        k.at<double>(2, 2) != 1) {
      diagnostics.error(file, "'camera_matrix' is not [fx 0 cx; 0 fy cy; 0 0 1] (skew or a last row other than 0 0 1)");
      return std::nullopt;
    }
    c.fx = k.at<double>(0, 0);
    c.fy = k.at<double>(1, 1);
    c.cx = k.at<double>(0, 2);
    c.cy = k.at<double>(1, 2);
    if (!dn.empty()) {
      if (!dn.isMap()) {
        diagnostics.error(file, "'distortion_coefficients' is not an !!opencv-matrix");
        return std::nullopt;
      }
      if (!smallMatrix(dn, 14)) {  // 14 x 14 doubles at most: then the count below
        diagnostics.error(file, "'distortion_coefficients' has no whole-number rows and cols of 1 to 14: not the "
                                "1xN or Nx1 !!opencv-matrix of OpenCV's models (4, 5, 8, 12 or 14 values)");
        return std::nullopt;
      }
      if (const std::string why = matrixDataProblem(dn); !why.empty()) {
        diagnostics.error(file, "'distortion_coefficients': " + why);
        return std::nullopt;
      }
      dn >> d;
      const int n = static_cast<int>(d.total());
      if (d.channels() != 1 || (d.rows != 1 && d.cols != 1) || !(n == 4 || n == 5 || n == 8 || n == 12 || n == 14)) {
        diagnostics.error(file, "'distortion_coefficients' has " + std::to_string(n) +
                                    " values; OpenCV's models have 4, 5, 8, 12 or 14");
        return std::nullopt;
      }
      d.convertTo(d, CV_64F);
      for (int i = 0; i < n; ++i) {
        const double v = d.at<double>(i);
        if (i < 5) c.distortion[static_cast<std::size_t>(i)] = v;
        else if (v != 0.0) {
          diagnostics.error(file, "'distortion_coefficients' value " + std::to_string(i + 1) + " is " + num(v) +
                                      ": only k1 k2 p1 p2 k3 are supported (the rational and prism terms must be 0)");
          return std::nullopt;
        }
      }
    }
  } catch (const cv::Exception& e) {
    const char* shifted = withoutHeader ? " (its line numbers count a %YAML:1.0 line put before the file)" : "";
    diagnostics.error(file, std::string("OpenCV cannot parse it: ") + e.what() + shifted);
    return std::nullopt;
  } catch (const std::exception& e) {
    // OpenCV's parsers let the standard library's exceptions out too: a YAML key with no name
    // (": [ 1 ]") gives std::length_error from basic_string, which would end the program.
    diagnostics.error(file, std::string("OpenCV cannot parse it (") + e.what() + ")");
    return std::nullopt;
  }
  if (const std::string p = c.problem(); !p.empty()) {
    diagnostics.error(file, p);
    return std::nullopt;
  }
  return c;
}

bool writeCameraModel(const std::string& file, const CameraModel& camera, const CalibrationFacts* facts,
                      Diagnostics& diagnostics) {
  if (const std::string p = camera.problem(); !p.empty()) {
    diagnostics.error(file, "not written: " + p);
    return false;
  }
  try {
    cv::FileStorage fs(file, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) {
      diagnostics.error(file, "cannot be written");
      return false;
    }
    if (facts) fs << "nframes" << facts->views;
    fs << "image_width" << camera.width << "image_height" << camera.height;
    if (facts) {
      fs << "board_width" << facts->boardColumns << "board_height" << facts->boardRows;
      fs << "square_size" << facts->squareSize;
    }
    const cv::Mat k = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    cv::Mat d(5, 1, CV_64F);
    for (int i = 0; i < 5; ++i) d.at<double>(i) = camera.distortion[static_cast<std::size_t>(i)];
    fs << "camera_matrix" << k << "distortion_coefficients" << d;
    if (facts && facts->rmsReprojectionError >= 0) fs << "avg_reprojection_error" << facts->rmsReprojectionError;
    fs.release();
  } catch (const cv::Exception& e) {
    diagnostics.error(file, std::string("cannot be written: ") + e.what());
    return false;
  }
  return true;
}

}  // namespace marionette::ar
