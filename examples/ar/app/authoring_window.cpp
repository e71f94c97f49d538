#include "authoring_window.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>

#include "augmentation_scene.hpp"
#include "marionette/core/text_file.hpp"

namespace marionette::ar {

namespace {

constexpr float kClickSlopPixels = 4.0f;     // a press and release closer than this is a click
constexpr float kFreeTurnDegreesPerPixel = 0.5f;

}  // namespace

// The synthetic input: low-level steps by frame, expanded from the file's events.
struct AuthoringWindow::Script {
  enum class Kind { MoveImage, MoveButton, Press, Release, Key, Quit };
  struct Step {
    long frame = 0;
    Kind kind = Kind::Quit;
    glm::vec2 at{0.0f};
    std::string label{};
    int button = 0, key = 0;
    bool shift = false, ctrl = false;
  };
  std::vector<Step> steps;
  std::size_t next = 0;
  ImVec2 mouse{-1.0f, -1.0f};
  bool down[2] = {false, false};
  std::map<std::string, ImVec4> buttons;  // label -> rect of the last frame (min x, min y, max x, max y)
};

AuthoringWindow::AuthoringWindow(AuthoringSession session, std::vector<std::string> bmlChoices, std::string outPath)
    : session_(std::move(session)), bml_(std::move(bmlChoices)), out_(std::move(outPath)) {
  exposure_ = session_.augmentation().exposureEv;
}

AuthoringWindow::~AuthoringWindow() {
  if (!initialized_) return;
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

bool AuthoringWindow::init(GLFWwindow* window, Diagnostics& diagnostics) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; no imgui.ini next to the user's files
  ImGui::StyleColorsDark();
  if (!ImGui_ImplGlfw_InitForOpenGL(window, true) || !ImGui_ImplOpenGL3_Init("#version 330")) {
    diagnostics.error("", "Dear ImGui's GLFW / OpenGL 3 backends did not start");
    ImGui::DestroyContext();
    return false;
  }
  initialized_ = true;
  return true;
}

bool AuthoringWindow::loadInputScript(const std::string& path, Diagnostics& diagnostics) {
  std::string text;
  if (!readTextFile(path, text, diagnostics)) return false;
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // The message keeps its old text, path included: a test looks for "FILE: not JSON".
    diagnostics.error(path, path + ": not JSON: " + e.what());
    return false;
  }
  if (!root.is_object() || !root.contains("events") || !root["events"].is_array()) {
    diagnostics.error(path, "'events': expected an array");
    return false;
  }
  auto script = std::make_unique<Script>();
  using Kind = Script::Kind;
  const nlohmann::json& events = root["events"];
  for (std::size_t i = 0; i < events.size(); ++i) {
    const nlohmann::json& e = events[i];
    const std::string where = "'events[" + std::to_string(i) + "]'";
    auto pixel = [&](const nlohmann::json& v, glm::vec2& out) {
      if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) return false;
      out = {v[0].get<float>(), v[1].get<float>()};
      return std::isfinite(out.x) && std::isfinite(out.y);
    };
    if (!e.is_object() || !e.contains("frame") || !e["frame"].is_number_integer() || e["frame"].get<long>() < 0) {
      diagnostics.error(path, where + ": expected an object with a whole \"frame\" >= 0");
      return false;
    }
    const long f = e["frame"].get<long>();
    Script::Step s;
    s.frame = f;
    if (e.contains("clickImage") || e.contains("dragImage")) {
      glm::vec2 a, b;
      const bool drag = e.contains("dragImage");
      const bool ok = drag ? e["dragImage"].is_array() && e["dragImage"].size() == 2 && pixel(e["dragImage"][0], a) &&
                                 pixel(e["dragImage"][1], b)
                           : pixel(e["clickImage"], a);
      if (!ok) {
        diagnostics.error(path,
                          where + ": expected " + (drag ? "\"dragImage\": [[x, y], [x, y]]" : "\"clickImage\": [x, y]"));
        return false;
      }
      script->steps.push_back({f, Kind::MoveImage, a});
      script->steps.push_back({f + 1, Kind::Press, a});
      if (drag) {
        script->steps.push_back({f + 2, Kind::MoveImage, 0.5f * (a + b)});
        script->steps.push_back({f + 3, Kind::MoveImage, b});
      }
      script->steps.push_back({drag ? f + 4 : f + 2, Kind::Release, drag ? b : a});
    } else if (e.contains("clickButton") && e["clickButton"].is_string()) {
      const std::string label = e["clickButton"].get<std::string>();
      script->steps.push_back({f, Kind::MoveButton, {}, label});
      script->steps.push_back({f + 1, Kind::Press, {}, label});
      script->steps.push_back({f + 2, Kind::Release, {}, label});
    } else if (e.contains("key") && e["key"].is_string() && e["key"].get<std::string>().size() == 1) {
      const char k = static_cast<char>(std::toupper(static_cast<unsigned char>(e["key"].get<std::string>()[0])));
      if (!((k >= 'A' && k <= 'Z') || (k >= '0' && k <= '9'))) {
        diagnostics.error(path, where + ": \"key\" must be a letter or a digit");
        return false;
      }
      s.kind = Kind::Key;
      s.key = k;  // GLFW's key codes for letters and digits are their ASCII codes
      s.shift = e.value("shift", false);
      s.ctrl = e.value("ctrl", false);
      script->steps.push_back(s);
    } else if (e.value("quit", false)) {
      s.kind = Kind::Quit;
      script->steps.push_back(s);
    } else {
      diagnostics.error(path, where + ": expected one of clickImage, dragImage, clickButton, key, quit");
      return false;
    }
  }
  std::stable_sort(script->steps.begin(), script->steps.end(),
                   [](const Script::Step& a, const Script::Step& b) { return a.frame < b.frame; });
  script_ = std::move(script);
  return true;
}

bool AuthoringWindow::placement(const std::string& character, glm::mat4& anchor) const {
  for (const PlacedCharacter& c : session_.augmentation().characters)
    if (c.name == character) {
      anchor = placementMatrix(c.placement);
      return true;
    }
  return false;
}

void AuthoringWindow::applyAction(Action a, const AuthoringView& view, long frameNumber) {
  a.frame = frameNumber;
  Diagnostics refused;
  if (!session_.apply(a, view, refused)) {  // the panel's status line: the reason, no file
    message_ = actionName(a.kind);
    for (const Diagnostic& d : refused.items) message_ += ": " + d.message;
    return;
  }
  modelled_ += modelledSeconds(a, previous_ ? &*previous_ : nullptr);
  previous_ = a;
  recorded_.push_back(a);
  message_ = std::string(actionName(a.kind)) + " done";
  if (a.kind == ActionKind::Save) save();
}

void AuthoringWindow::save() {
  Diagnostics d;
  if (!writeAugmentation(out_, relativeTo(session_.augmentation(), out_), d)) {
    message_ = d.format();
    return;
  }
  const std::string actions = std::filesystem::path(out_).replace_extension(".actions.json").string();
  std::ofstream(actions, std::ios::trunc) << formatActions(recorded_);
  ++savesWritten_;
  std::printf("marionette-ar: authoring: saved %s (and the actions in %s)\n", out_.c_str(), actions.c_str());
  message_ = "saved " + std::filesystem::path(out_).filename().string();
}

void AuthoringWindow::frame(long frameNumber, const AuthoringView& view, const char* trackingState, int windowWidth,
                            int windowHeight) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGuiIO& io = ImGui::GetIO();
  const float toImageX = static_cast<float>(view.width) / static_cast<float>(std::max(1, windowWidth));
  const float toImageY = static_cast<float>(view.height) / static_cast<float>(std::max(1, windowHeight));
  if (script_) {  // the script's input replaces the devices': same fields the backend fills
    Script& s = *script_;
    for (bool& k : io.KeysDown) k = false;
    io.KeyShift = io.KeyCtrl = false;
    for (; s.next < s.steps.size() && s.steps[s.next].frame <= frameNumber; ++s.next) {
      const Script::Step& step = s.steps[s.next];
      auto target = [&]() -> ImVec2 {
        if (step.label.empty()) return {step.at.x / toImageX, step.at.y / toImageY};
        const auto it = s.buttons.find(step.label);
        if (it == s.buttons.end()) {
          message_ = "input script: no button \"" + step.label + "\"";
          return s.mouse;
        }
        return {0.5f * (it->second.x + it->second.z), 0.5f * (it->second.y + it->second.w)};
      };
      switch (step.kind) {
        case Script::Kind::MoveImage:
        case Script::Kind::MoveButton: s.mouse = target(); break;
        case Script::Kind::Press: s.down[step.button] = true; break;
        case Script::Kind::Release: s.down[step.button] = false; break;
        case Script::Kind::Key:
          io.KeysDown[step.key] = true;
          io.KeyShift = step.shift;
          io.KeyCtrl = step.ctrl;
          break;
        case Script::Kind::Quit: quit_ = true; break;
      }
    }
    io.MousePos = s.mouse;
    io.MouseDown[0] = s.down[0];
    io.MouseDown[1] = s.down[1];
  }
  ImGui::NewFrame();

  // The image: clicks, drags and free turns where the panel does not take the mouse.
  auto imagePixel = [&](glm::vec2 p) { return glm::vec2(p.x * toImageX, p.y * toImageY); };
  const glm::vec2 mouse(io.MousePos.x, io.MousePos.y);
  for (int b = 0; b < 2; ++b) {
    if (ImGui::IsMouseClicked(b) && !io.WantCaptureMouse) {
      pressAt_[b] = mouse;
      pressing_[b] = true;
    }
    if (pressing_[b] && ImGui::IsMouseReleased(b)) {
      pressing_[b] = false;
      const glm::vec2 from = imagePixel(pressAt_[b]), to = imagePixel(mouse);
      const bool click = glm::length((to - from) / glm::vec2(toImageX, toImageY)) < kClickSlopPixels;
      if (b == 0 && click) applyAction({.kind = ActionKind::Place, .pixel = to}, view, frameNumber);
      else if (b == 0) applyAction({.kind = ActionKind::Drag, .pixel = from, .to = to}, view, frameNumber);
      else if (!click)
        applyAction({.kind = ActionKind::Rotate, .axes = ga::Axes::Global, .plane = RotationPlane::E31,
                     .value = (mouse.x - pressAt_[b].x) * kFreeTurnDegreesPerPixel},
                    view, frameNumber);
    }
  }
  // Keys.
  auto turn = [&](RotationPlane plane, float degrees) {
    applyAction({.kind = ActionKind::Rotate, .axes = axes_, .plane = plane, .value = degrees}, view, frameNumber);
  };
  if (!io.WantCaptureKeyboard) {
    const float sign = io.KeyShift ? -1.0f : 1.0f;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Z, false)) applyAction({.kind = ActionKind::Undo}, view, frameNumber);
    else if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_S, false)) applyAction({.kind = ActionKind::Save}, view, frameNumber);
    else if (ImGui::IsKeyPressed(GLFW_KEY_X, false)) turn(RotationPlane::E23, sign * kRotationStepDegrees);
    else if (ImGui::IsKeyPressed(GLFW_KEY_Y, false)) turn(RotationPlane::E31, sign * kRotationStepDegrees);
    else if (ImGui::IsKeyPressed(GLFW_KEY_Z, false)) turn(RotationPlane::E12, sign * kRotationStepDegrees);
    else if (ImGui::IsKeyPressed(GLFW_KEY_L, false))
      axes_ = axes_ == ga::Axes::Local ? ga::Axes::Global : ga::Axes::Local;
  }

  // The panel, at the window's top right.
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(windowWidth) - 198.0f, 8.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(190.0f, 0.0f), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.8f);
  ImGui::Begin("Authoring", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::Text("camera %s", trackingState);
  auto button = [&](const char* label) {
    const bool pressed = ImGui::Button(label);
    if (script_) {
      const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
      script_->buttons[label] = ImVec4(lo.x, lo.y, hi.x, hi.y);
    }
    return pressed;
  };
  // The scene's characters and the BML files, one button each (the picked one marked).
  const std::vector<CatalogueEntry>& entries = session_.catalogue();
  const int picked = session_.pickedEntry();
  ImGui::TextUnformatted("character:");
  for (std::size_t i = 0; i < entries.size(); ++i) {
    ImGui::SameLine();
    const bool isPicked = static_cast<int>(i) == picked;
    if (isPicked) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
    if (button(entries[i].name.c_str())) applyAction({.kind = ActionKind::PickCharacter, .name = entries[i].name}, view, frameNumber);
    if (isPicked) ImGui::PopStyleColor();
  }
  if (picked >= 0) {  // the height a click places it at, and why when that is not its file's own
    const LifeSize life = entries[static_cast<std::size_t>(picked)].lifeSize();
    ImGui::Text("life size %.2f m", static_cast<double>(life.metres));
    if (!life.note.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.85f, 0.4f, 1.0f));
      ImGui::TextWrapped("%s", life.note.c_str());
      ImGui::PopStyleColor();
    }
  }
  ImGui::TextUnformatted("BML:");
  for (const std::string& f : bml_) {
    const std::string label = std::filesystem::path(f).filename().string();
    const bool isPicked = f == session_.pickedBml();
    if (isPicked) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
    if (button(label.c_str())) applyAction({.kind = ActionKind::PickBml, .name = f}, view, frameNumber);
    if (isPicked) ImGui::PopStyleColor();
  }
  ImGui::TextUnformatted("click: place, drag: move");
  int axes = axes_ == ga::Axes::Local ? 0 : 1;
  ImGui::RadioButton("local", &axes, 0);
  ImGui::SameLine();
  ImGui::RadioButton("global", &axes, 1);
  axes_ = axes == 0 ? ga::Axes::Local : ga::Axes::Global;
  // Each button turns by the fixed step in one plane, named by the axis it turns about.
  const struct { const char* minus; const char* plus; RotationPlane plane; } turns[] = {
      {"X-", "X+", RotationPlane::E23}, {"Y-", "Y+", RotationPlane::E31}, {"Z-", "Z+", RotationPlane::E12}};
  for (const auto& t : turns) {
    if (button(t.minus)) turn(t.plane, -kRotationStepDegrees);
    ImGui::SameLine();
    if (button(t.plus)) turn(t.plane, kRotationStepDegrees);
    ImGui::SameLine();
    ImGui::Text("%s", planeName(t.plane));
  }
  const int placedIndex = session_.pickedCharacter();
  if (placedIndex >= 0) {
    const PlacedCharacter& c = session_.augmentation().characters[static_cast<std::size_t>(placedIndex)];
    if (!ImGui::IsAnyItemActive()) height_ = entries[static_cast<std::size_t>(picked)].heightMetres * c.placement.scale;
    ImGui::SliderFloat("##height", &height_, 0.2f, 3.0f, "height %.2f m");
    if (ImGui::IsItemDeactivatedAfterEdit())
      applyAction({.kind = ActionKind::Height, .value = height_}, view, frameNumber);
  }
  if (!ImGui::IsAnyItemActive()) exposure_ = session_.augmentation().exposureEv;
  ImGui::SliderFloat("EV", &exposure_, -4.0f, 4.0f, "exposure %+.2f");
  if (ImGui::IsItemDeactivatedAfterEdit()) applyAction({.kind = ActionKind::Exposure, .value = exposure_}, view, frameNumber);
  if (button("Undo")) applyAction({.kind = ActionKind::Undo}, view, frameNumber);
  ImGui::SameLine();
  if (button("Save")) applyAction({.kind = ActionKind::Save}, view, frameNumber);
  ImGui::Text("%zu actions, %.1f s", recorded_.size(), modelled_);
  if (!message_.empty()) ImGui::TextWrapped("%s", message_.c_str());
  ImGui::End();

  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace marionette::ar
