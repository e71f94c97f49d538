// The authoring UI of the windowed renderer (`marionette-ar SCENE.json --author OUT.json`,
// docs/authoring.md): a Dear ImGui panel over the tracked camera image. Every operation, from the
// mouse, a key or a button, becomes an Action applied to an AuthoringSession, the same as a line
// of an action file replayed headless; Save writes the augmentation and the actions so far.
//
// Mouse over the image: a click places the picked character on the tracked floor, a left drag
// moves it, a right drag turns it freely about the world's vertical. Keys: X, Y, Z turn +15 deg
// in e23, e31, e12 (Shift: -15), L switches local / global axes, Ctrl+Z undoes, Ctrl+S saves.
//
// Synthetic input (--input-script FILE, for tests under Xvfb): the events go into ImGui's input
// state where the GLFW backend's would, so the panel and the image see them as a user's.
//   { "events": [ { "frame": 10, "clickImage": [320, 400] },     // image pixels
//                 { "frame": 20, "dragImage": [[320, 400], [300, 380]] },
//                 { "frame": 30, "clickButton": "Y+" },          // a panel button by its label
//                 { "frame": 40, "key": "Z", "shift": true },    // or "ctrl": true
//                 { "frame": 50, "quit": true } ] }
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "marionette_ar/authoring/authoring_session.hpp"

struct GLFWwindow;

namespace marionette::ar {

class AuthoringWindow {
 public:
  // `session` starts from the scene's tracker; `bmlChoices` are the files the BML list offers.
  AuthoringWindow(AuthoringSession session, std::vector<std::string> bmlChoices, std::string outPath);
  ~AuthoringWindow();
  AuthoringWindow(const AuthoringWindow&) = delete;
  AuthoringWindow& operator=(const AuthoringWindow&) = delete;

  // ImGui's context and its GLFW and OpenGL 3 backends on the renderer's window; false with an
  // error in `diagnostics` (no file: its `file` is empty) when a backend does not start.
  [[nodiscard]] bool init(GLFWwindow* window, Diagnostics& diagnostics);
  // Synthetic input; errors in `diagnostics` name the file and the event ('events[3]').
  [[nodiscard]] bool loadInputScript(const std::string& path, Diagnostics& diagnostics);

  // One frame, after the scene is presented to the window and before the swap: the panel, the
  // input (the user's or the script's) turned into actions and applied through `view`, drawn.
  // `imageWidth` x `imageHeight` is the render target the view's pixels are in.
  void frame(long frameNumber, const AuthoringView& view, const char* trackingState, int windowWidth,
             int windowHeight);

  [[nodiscard]] const AuthoringSession& session() const noexcept { return session_; }
  // The placement a scene character is drawn with, and whether it is (placed in the session).
  [[nodiscard]] bool placement(const std::string& character, glm::mat4& anchor) const;
  [[nodiscard]] bool quitRequested() const noexcept { return quit_; }
  [[nodiscard]] int savesWritten() const noexcept { return savesWritten_; }

 private:
  struct Script;
  void applyAction(Action action, const AuthoringView& view, long frameNumber);
  void save();
  AuthoringSession session_;
  std::vector<std::string> bml_;
  std::string out_;
  std::unique_ptr<Script> script_;
  std::vector<Action> recorded_;
  bool initialized_ = false, quit_ = false;
  int savesWritten_ = 0;
  ga::Axes axes_ = ga::Axes::Global;
  float height_ = 0, exposure_ = 0;
  std::string message_;
  glm::vec2 pressAt_[2] = {};  // window pixels where each mouse button went down on the image
  bool pressing_[2] = {false, false};
  std::optional<Action> previous_;
  double modelled_ = 0;
};

}  // namespace marionette::ar
