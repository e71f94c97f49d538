#include "marionette_ar/render/contact_shadow_renderer.hpp"

#include <epoxy/gl.h>

#include <algorithm>

namespace marionette::ar {

ContactShadowRenderer::~ContactShadowRenderer() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (!maps_.empty()) glDeleteTextures(static_cast<GLsizei>(maps_.size()), maps_.data());
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

bool ContactShadowRenderer::create(std::size_t slots, Diagnostics& diagnostics) {
  if (!depthProgram_.build("character.vert", "shadow_depth.frag", diagnostics) ||
      !catcherProgram_.build("shadow_catcher.vert", "shadow_catcher.frag", diagnostics))
    return false;
  // Depth textures read as plain samplers (nearest, compared in the shader): the same on GL 3.3
  // and ES 3.0, where depth textures cannot be filtered.
  maps_.assign(std::max<std::size_t>(slots, 1), 0u);
  glGenTextures(static_cast<GLsizei>(maps_.size()), maps_.data());
  for (const unsigned map : maps_) {
    glBindTexture(GL_TEXTURE_2D, map);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, kMapSize, kMapSize, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT,
                 nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, maps_[0], 0);
  const GLenum none = GL_NONE;
  glDrawBuffers(1, &none);
  glReadBuffer(GL_NONE);
  const bool complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (!complete) {
    diagnostics.error("", "the contact shadow's depth framebuffer is incomplete");
    return false;
  }
  glGenVertexArrays(1, &vao_);  // core profile: a draw needs a bound VAO even without attributes
  return true;
}

void ContactShadowRenderer::renderMap(std::size_t slot, const CharacterModel& model, const CharacterPose& pose,
                                      const glm::mat4& world, const glm::mat4& lightViewProjection) {
  if (slot >= maps_.size()) return;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, maps_[slot], 0);
  glViewport(0, 0, kMapSize, kMapSize);
  glClearDepthf(1.0f);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  drawCharacter(depthProgram_, model, pose, world, lightViewProjection, Lighting{}, nullptr, 1.0f);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void ContactShadowRenderer::drawCatcher(std::size_t slot, const glm::mat4& viewProjection,
                                        const ContactShadowDraw& shadow) const {
  if (!(shadow.strength > 0.0f) || slot >= maps_.size()) return;
  const ShaderProgram& p = catcherProgram_;
  p.use();
  p.set("uViewProjection", viewProjection);
  p.set("uCatcherCentre", glm::vec4(shadow.centre, shadow.axis));
  p.set("uCatcherHalfSize", glm::vec4(shadow.halfSize, 0.0f, 0.0f));
  p.set("uLightViewProjection", shadow.lightViewProjection);
  p.set("uHasDirect", shadow.hasDirect ? 1 : 0);
  p.set("uTexel", 1.0f / static_cast<float>(kMapSize));
  p.set("uTanSoftness", shadow.tanSoftness);
  p.set("uDirectFraction", shadow.directFraction);
  p.set("uAmbientFraction", shadow.ambientFraction);
  p.set("uStrength", shadow.strength);
  const int contacts = static_cast<int>(std::min<std::size_t>(shadow.contacts.size(), 8));
  if (contacts > 0) glUniform4fv(p.location("uContacts"), contacts, &shadow.contacts[0].x);
  p.set("uContactCount", contacts);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, maps_[slot]);
  p.set("uShadowMap", 0);
  setOcclusionUniforms(p, shadow.occlusion, 4);
  // Over the image drawn so far, multiplied in; the floor is no surface of the depth buffer.
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_DST_COLOR, GL_ZERO);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  glBindTexture(GL_TEXTURE_2D, 0);
}

}  // namespace marionette::ar
