// Work-precision of the gaze smoothing (docs/accuracy.md): the critically damped
// spring x'' = w^2 (g - x) - 2 w x' that gaze angles follow, stepped four ways, for
// frame steps from 1/240 s to 0.5 s. The target moves smoothly (two sines, up to
// 1.4 rad/s), so even the exact steps have an error: they see the target only at
// the frame's ends.
// Reference: the ODE itself, integrated by classical RK4 in double precision at
// steps of at most 10 microseconds against the continuous target; none of the
// methods under test (DampedAngle's closed forms) takes part in it.
//   marionette_gaze_work_precision OUT.csv
// Columns: method, dt_s, max_error_rad, ns_per_step, ns_per_simulated_second,
// frames_compared (the frames the error is over), frames (the run's), diverged (1 when
// the method left the reference by more than 1e3 rad or became non-finite; its
// max_error_rad is then "inf", over the frames before it diverged: not a figure),
// mean_error_rad (the mean over the same frames; "inf" when diverged);
// one block per method, separated by two blank lines (gnuplot's `index`).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include "marionette/behavior/gaze.hpp"

using namespace marionette;

namespace {
constexpr float kTimeConstant = 0.12f;  // GazeSettings' default
constexpr double kSeconds = 6.0;

double target(double t) { return 0.8 * std::sin(1.3 * t) + 0.1 * std::sin(3.7 * t); }

struct State {
  float x = 0.0f, v = 0.0f;
};
// Each method sees the target at the start (g0) and end (g1) of the frame, as the
// runtime does (it keeps the last frame's target).
using Step = std::function<void(State&, float g0, float g1, float dt)>;

// Exact for a target held at its end-of-frame value.
void exactHold(State& s, float, float g1, float dt) {
  DampedAngle a{s.x, s.v};
  a.step(g1, dt, kTimeConstant, 1e9f);  // no speed limit: the pure spring
  s.x = a.value;
  s.v = a.velocity;
}

// Exact for a target moving linearly from g0 to g1 over the frame.
void exactRamp(State& s, float g0, float g1, float dt) {
  DampedAngle a{s.x, s.v};
  a.stepRamp(g0, g1, dt, kTimeConstant, 1e9f);
  s.x = a.value;
  s.v = a.velocity;
}

void semiImplicitEuler(State& s, float, float g, float dt) {
  const float w = 1.0f / kTimeConstant;
  s.v += (w * w * (g - s.x) - 2.0f * w * s.v) * dt;
  s.x += s.v * dt;
}

void explicitEuler(State& s, float, float g, float dt) {
  const float w = 1.0f / kTimeConstant;
  const float a = w * w * (g - s.x) - 2.0f * w * s.v;
  s.x += s.v * dt;
  s.v += a * dt;
}

// The reference: x'' = w^2 (g(t) - x) - 2 w x' from t0 over dt, classical RK4 in
// double at n equal steps of at most 10 microseconds (its own error, of order
// (w h)^4 per unit time, is far below float precision).
struct Exact {
  double x = 0.0, v = 0.0;
};
void integrateSpring(Exact& s, double t0, double dt) {
  const double w = 1.0 / static_cast<double>(kTimeConstant);
  const auto accel = [w](double t, double x, double v) { return w * w * (target(t) - x) - 2.0 * w * v; };
  const int n = std::max(1, static_cast<int>(std::ceil(dt / 1e-5)));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) {
    const double t = t0 + h * i, x = s.x, v = s.v;
    const double k1x = v, k1v = accel(t, x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = accel(t + 0.5 * h, x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = accel(t + 0.5 * h, x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = accel(t + h, x + h * k3x, v + h * k3v);
    s.x = x + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
    s.v = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
  }
}

// Max |x - reference| at the frame times, and over how many frames it was taken.
struct Error {
  double max = 0.0, sum = 0.0;  // over the frames compared
  int framesCompared = 0, frames = 0;
  bool diverged = false;
};
Error maxError(const Step& step, double dt) {
  State s;
  Exact ref;
  Error error;
  error.frames = static_cast<int>(std::ceil(kSeconds / dt - 1e-9));
  for (int i = 0; i < error.frames; ++i) {
    const double t = i * dt;
    step(s, static_cast<float>(target(t)), static_cast<float>(target(t + dt)), static_cast<float>(dt));
    integrateSpring(ref, t, dt);
    const double e = std::fabs(static_cast<double>(s.x) - ref.x);
    if (!std::isfinite(e) || e > 1e3) {
      error.diverged = true;
      error.max = HUGE_VAL;
      return error;
    }
    ++error.framesCompared;
    error.max = std::max(error.max, e);
    error.sum += e;
  }
  return error;
}

double nsPerStep(const Step& step) {
  State s;
  constexpr int kSteps = 2000000;
  volatile float sink = 0.0f;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < kSteps; ++i) {
    step(s, (i & 1024) ? 1.0f : -1.0f, (i & 1024) ? 1.0f : -0.9f, 1.0f / 60.0f);
    sink = sink + s.x;
  }
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / kSteps;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUT.csv\n", argv[0]);
    return 2;
  }
  std::FILE* out = std::fopen(argv[1], "w");
  if (!out) {
    std::fprintf(stderr, "%s: cannot write\n", argv[1]);
    return 2;
  }
  std::printf("reference: RK4 of the spring ODE in double, steps <= 1e-5 s, continuous target\n");
  std::fprintf(out, "method,dt_s,max_error_rad,ns_per_step,ns_per_simulated_second,frames_compared,frames,diverged,mean_error_rad\n");
  const std::pair<const char*, Step> methods[] = {
      {"exact (target ramp)", exactRamp},
      {"exact (target held)", exactHold},
      {"semi-implicit Euler", semiImplicitEuler},
      {"explicit Euler", explicitEuler}};
  bool first = true;
  for (const auto& [name, step] : methods) {
    if (!first) std::fprintf(out, "\n\n");  // a gnuplot data block per method
    first = false;
    const double ns = nsPerStep(step);
    for (double dt : {1.0 / 240, 1.0 / 120, 1.0 / 60, 1.0 / 30, 0.1, 0.25, 0.5}) {
      const Error e = maxError(step, dt);
      char error[32] = "inf";
      char mean[32] = "inf";
      if (!e.diverged) {
        std::snprintf(error, sizeof error, "%.6g", e.max);
        std::snprintf(mean, sizeof mean, "%.6g", e.sum / e.framesCompared);
      }
      std::fprintf(out, "%s,%.6f,%s,%.3f,%.1f,%d,%d,%d,%s\n", name, dt, error, ns, ns / dt, e.framesCompared, e.frames,
                   e.diverged ? 1 : 0, mean);
      if (e.diverged)
        std::printf("%-20s dt %.4f s  diverged after %d of %d frames  %.2f ns/step\n", name, dt, e.framesCompared,
                    e.frames, ns);
      else
        std::printf("%-20s dt %.4f s  max error %.3g rad (mean %.3g) over %d frames  %.2f ns/step\n", name, dt, e.max,
                    e.sum / e.framesCompared, e.frames, ns);
    }
  }
  std::fclose(out);
  return 0;
}
