// Locomotion: a character walks or runs to a target, along waypoints, or to
// another character, and stops facing as asked.
//
// Two parts. Steering is kinematic and deterministic: the heading turns toward
// the next waypoint at a bounded angular speed, the speed accelerates toward the
// cruise speed and brakes on the curve v = sqrt(2 a d) so that it reaches zero at
// the destination; both are clamped per step, so any dt (0 to 1 s and beyond) is
// stable. The gait follows the speed: the walk and run clips are blended by speed
// (run weight (v - v_walk) / (v_run - v_walk)) and played at one shared phase, the
// clips aligned at their left-foot strike, the phase advancing by v / D per
// second where D is the distance the blend covers in one cycle; so the feet cover
// the ground the character covers. The world translation is the clips' root
// motion over the step (clips without root travel move at their measured ground
// speed, the speed of the stance foot backwards), which keeps the within-cycle
// surges that planted feet need.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "marionette/animation/sampling.hpp"
#include "marionette/behavior/behavior_request.hpp"
#include "marionette/behavior/foot_planting.hpp"
#include "marionette/core/transform.hpp"
#include "marionette/skeleton/skeleton.hpp"

namespace marionette {

struct AnimationClip;
class Rig;
struct RigJoints;

struct LocomotionSettings {
  float walkSpeed = 0.0f;           // m/s for manner WALK; 0 = the walk clip's own ground speed
  float runSpeed = 0.0f;            // m/s for RUN (and JOG); 0 = the run clip's own
  float turnSpeed = 3.0f;           // rad/s: the bounded angular speed, walking or turning in place
  float acceleration = 2.0f;        // m/s^2
  float deceleration = 2.0f;        // m/s^2, braking toward the destination
  float arriveRadius = 0.02f;       // m: at the destination this close
  float waypointRadius = 0.3f;      // m: an intermediate waypoint is passed this close
  float characterProximity = 1.0f;  // m: stop this far from a target character
  float facingTolerance = 0.005f;   // rad: final facing reached
  float blendTimeConstant = 0.15f;  // s: lag of the gait's weight over the posture behind the speed
  FootPlantSettings feet;           // foot planting (on by default)
};

// A gait clip of the locomotion set, analysed once.
struct GaitClip {
  std::shared_ptr<const AnimationClip> clip;
  float groundSpeed = 0.0f;  // m/s travelled at playback rate 1
  float strikePhase = 0.0f;  // cycle phase in [0, 1) at which the left foot becomes the stance foot
  bool hasRootMotion = false;
  float floor[2] = {0.0f, 0.0f};  // lowest model height of the left and right foot over the cycle
  float lateralDrift = 0.0f;      // sideways root travel over a whole cycle (detrends the sway)
  // Each foot's model place over the cycle (left, right), evenly sampled from clip
  // time 0, as the gait plays the clip (in place when it travels).
  std::vector<glm::vec3> footPath[2];
  [[nodiscard]] float duration() const noexcept;
  [[nodiscard]] float cycleDistance() const noexcept { return groundSpeed * duration(); }
  // A foot's model place at an unwrapped gait phase (strike-aligned), interpolated; zero without a path.
  [[nodiscard]] glm::vec3 footAt(int foot, double phase) const noexcept;
};

struct LocomotionSet {
  GaitClip walk, run;              // run.clip may be null: walk only
  std::vector<std::string> notes;  // what was found or assumed, for logs
  [[nodiscard]] bool usable() const noexcept { return walk.clip && walk.groundSpeed > 0.0f; }
};

// Ground speed and strike phase of a looping gait clip. The stance foot at each
// instant is the lower of the two feet; the ground speed is the clip's root travel
// per second, or for an in-place clip the stance foot's mean horizontal speed.
[[nodiscard]] GaitClip analyzeGait(std::shared_ptr<const AnimationClip> clip, const Skeleton& skeleton, int leftFoot,
                                   int rightFoot);
// The set from the rig's profile: its walk and run clips, feet from its legs.
[[nodiscard]] LocomotionSet makeLocomotionSet(const Rig& rig);

// Where to go and how fast, made from a request's LocomotionParameters.
struct LocomotionPlan {
  std::vector<glm::vec2> waypoints;  // world (x, z); the last one is the destination
  std::string targetCharacter;       // go to this character (its place is resolved every frame)
  float speed = 0.0f;                // cruise speed, m/s
  float proximity = 0.0f;            // stop this far from the destination
  bool hasFacing = false;
  float facing = 0.0f;               // world heading at arrival, radians (0 faces +Z)
  bool faceTargetCharacter = false;  // turn to the target character on arrival
};

// The plan for `parameters` on this gait set: waypoints or a target character;
// the speed from the manner (Walk, Run, Stroll: half the walk speed, Sprint: 1.3 x
// run) unless `speed` is given; facing and proximity. Returns "" or why the request
// cannot be performed (no target, a waypoint that is not finite, too many); `warning`
// notes values out of range that were ignored (speed, facing, proximity).
[[nodiscard]] std::string makeLocomotionPlan(const LocomotionParameters& parameters, const LocomotionSet& set,
                                             const LocomotionSettings& settings, LocomotionPlan& plan,
                                             std::string& warning);

// The kinematic state.
struct SteeringState {
  glm::vec2 position{0.0f};  // world (x, z)
  float heading = 0.0f;      // radians about +Y; 0 faces +Z
  float speed = 0.0f;        // m/s along the heading
  std::size_t waypoint = 0;  // the one being walked to
  bool arrived = false;      // at the destination
  bool done = false;         // arrived and facing as asked
};
// One step of dt toward `waypoints` (the plan's, or a target character's place):
// turns and sets the speed (see the top of this file). Returns the longest
// distance the character may travel this step (so as not to pass the destination).
float steer(SteeringState& state, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
            const LocomotionSettings& settings, float dt) noexcept;
// Moves by `travel` (world x, z), passes waypoints, arrives, then turns to the facing.
void advance(SteeringState& state, const LocomotionPlan& plan, std::span<const glm::vec2> waypoints,
             const LocomotionSettings& settings, const glm::vec2& travel) noexcept;
// Seconds from `from` to done, simulated at 60 Hz at the cruise speed (for BML
// sync points; the controller fires the end on the real arrival). At most 4 hours.
[[nodiscard]] double estimateLocomotionSeconds(SteeringState from, const LocomotionPlan& plan,
                                               std::span<const glm::vec2> waypoints, const LocomotionSettings& settings);

// A character's locomotion: exists once the character got a locomotion request.
// Command time: the constructor and start(); per frame: update() (no allocation).
class LocomotionController {
 public:
  LocomotionController(std::shared_ptr<const LocomotionSet> set, const Skeleton& skeleton, const RigJoints& joints);

  // Follows `plan` from now, keeping the current speed and gait phase.
  void start(std::shared_ptr<const LocomotionPlan> plan, const glm::vec3& position, float heading) noexcept;
  // Stops where it is (braking), e.g. when the request was cancelled.
  void stop() noexcept;
  // The current target character's position (resolved before the frame).
  void setTargetPosition(const glm::vec3& world) noexcept;

  // Steers, advances the gait, moves `position` / `heading`, and blends the gait
  // over `pose` (weight rising with speed). `scratch` is any pose-sized buffer.
  void update(float dt, double clock, glm::vec3& position, float& heading, const Skeleton& skeleton,
              std::span<Transform> pose, std::span<Transform> scratch) noexcept;
  [[nodiscard]] const FootPlanter& feet() const noexcept { return planter_; }

  [[nodiscard]] bool moving() const noexcept { return plan_ && !state_.done; }
  [[nodiscard]] double doneTime() const noexcept { return doneTime_; }  // clock of the last arrival; < 0 none
  [[nodiscard]] const SteeringState& steering() const noexcept { return state_; }
  [[nodiscard]] float weight() const noexcept { return weight_; }        // of the gait over the posture
  [[nodiscard]] float runWeight() const noexcept { return runWeight_; }
  [[nodiscard]] double phase() const noexcept { return phase_; }
  [[nodiscard]] const LocomotionSet& set() const noexcept { return *set_; }
  void setSettings(const LocomotionSettings& s) noexcept { settings_ = s; }
  [[nodiscard]] const LocomotionSettings& settings() const noexcept { return settings_; }

 private:
  [[nodiscard]] std::span<const glm::vec2> waypoints() const noexcept;  // plan_ must be set
  // The gait phase in [0, 1) whose stance foot (the lower one) is nearest, across
  // the ground, to where `posture` has that foot; the current phase without feet.
  [[nodiscard]] double stanceMatchingPhase(const Skeleton& skeleton, std::span<const Transform> posture) const noexcept;

  std::shared_ptr<const LocomotionSet> set_;
  std::shared_ptr<const LocomotionPlan> plan_;
  LocomotionSettings settings_;
  SteeringState state_;
  glm::vec2 targetPosition_{0.0f};
  glm::vec3 drawnAt_{0.0f};  // where update() last put the character (steering place + sway)
  double phase_ = 0.0;  // cycles, unwrapped
  float weight_ = 0.0f, runWeight_ = 0.0f;
  double doneTime_ = -1.0;
  std::vector<Transform> gaitPose_;
  FootPlanter planter_;
  int feetJoints_[2] = {-1, -1};
  SamplingCursor walkCursor_, walkRootCursor_, runCursor_, runRootCursor_;
};

}  // namespace marionette
