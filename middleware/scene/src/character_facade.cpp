// Character's public calls, each handed to its private state (character_state.hpp).
#include "character_state.hpp"

namespace marionette {

Character::Character(std::string name, std::shared_ptr<const Rig> rig)
    : state_(std::make_unique<State>(*this, std::move(name), std::move(rig))) {}
Character::~Character() = default;

const std::string& Character::name() const noexcept { return state_->name_; }
const Rig& Character::rig() const noexcept { return *state_->rig_; }
const Skeleton& Character::skeleton() const noexcept { return state_->skeleton(); }
const TransformBuffer& Character::transformBuffer() const noexcept { return state_->buffer_; }
TransformBuffer& Character::transformBuffer() noexcept { return state_->buffer_; }
std::span<const Transform> Character::localPose() const noexcept { return state_->pose_; }
const CharacterStats& Character::stats() const noexcept { return state_->stats_; }

void Character::setPosition(const glm::vec3& p) noexcept { state_->setPosition(p); }
void Character::setHeading(float radians) noexcept { state_->setHeading(radians); }
glm::vec3 Character::position() const noexcept { return state_->position_; }
float Character::heading() const noexcept { return state_->heading_; }
glm::mat4 Character::worldMatrix() const noexcept { return state_->worldMatrix(); }
PlacementDelta Character::lastMotion() const noexcept { return state_->lastMotion_; }

bool Character::play(int layer, std::shared_ptr<const AnimationClip> clip, const PlayOptions& options) {
  return state_->play(layer, std::move(clip), options);
}
bool Character::play(int layer, std::string_view clipName, const PlayOptions& options) {
  return state_->play(layer, clipName, options);
}
void Character::stop(int layer, float fadeOut) { state_->stop(layer, fadeOut); }
int Character::layerCount() const noexcept { return state_->layerCount(); }
double Character::layerTime(int layer) const noexcept { return state_->layerTime(layer); }

BehaviorResult Character::addBehavior(BehaviorRequest request) { return state_->addBehavior(std::move(request)); }
bool Character::cancelBehavior(std::string_view id, double blendOut) { return state_->cancelBehavior(id, blendOut); }
std::size_t Character::cancelBehaviors(std::string_view idPrefix, double blendOut) {
  return state_->cancelBehaviors(idPrefix, blendOut);
}
const BehaviorTimeline& Character::behaviors() const noexcept { return state_->behaviors_; }
double Character::time() const noexcept { return state_->clock_; }

void Character::setLocomotionSettings(const LocomotionSettings& settings) noexcept {
  state_->setLocomotionSettings(settings);
}
const LocomotionSettings& Character::locomotionSettings() const noexcept { return state_->locomotionSettings_; }
const LocomotionController* Character::locomotion() const noexcept { return state_->locomotion_.get(); }
LocomotionStatus Character::locomotionStatus(std::string_view id) const noexcept { return state_->locomotionStatus(id); }
std::optional<double> Character::estimateLocomotion(const BehaviorRequest& request) const {
  return state_->estimateLocomotion(request);
}
const LocomotionSet& Character::locomotionSet() const { return state_->locomotionSet(); }

std::shared_ptr<const speech::SpokenLine> Character::prepareSpeech(const BehaviorRequest& request,
                                                                   Diagnostics& diagnostics) const {
  return state_->prepareSpeech(request, diagnostics);
}
std::shared_ptr<const speech::SpeechService::Preparation> Character::prepareSpeechInBackground(
    const BehaviorRequest& request) const {
  return state_->prepareSpeechInBackground(request);
}

void Character::setGazeSettings(const GazeSettings& settings) noexcept { state_->gazeSettings_ = settings; }
const GazeSettings& Character::gazeSettings() const noexcept { return state_->gazeSettings_; }
void Character::setPointingSettings(const PointingSettings& settings) noexcept { state_->pointingSettings_ = settings; }
const PointingSettings& Character::pointingSettings() const noexcept { return state_->pointingSettings_; }

void Character::update(double dt) noexcept { state_->update(dt); }

}  // namespace marionette
