// The shadow catcher: darkens the camera's image of the floor by the light the character takes
// away (docs/ar-renderer.md, "Contact shadows"). The light is the one that shades the
// character: a directional part (its shadow map, softened by the light's angular size with a
// blocker search: the penumbra widens with the occluder's height) and an ambient part (soft
// discs under the joints that touch the floor). Multiplied into the framebuffer (blend
// DST_COLOR, ZERO) in display space, so the darkening is applied to linear light.
in vec3 vWorld;
in vec2 vLocal;
out vec4 fragColor;

uniform sampler2D uShadowMap;       // the caster's depth from the light, 1 where nothing is
uniform mat4 uLightViewProjection;  // orthographic: uv and depth share one scale (2 radii)
uniform int uHasDirect;             // 0: no directional part (light below the floor, or none)
uniform float uTexel;               // one shadow map texel, in uv
uniform float uTanSoftness;         // tan of the light's angular radius
uniform float uDirectFraction;      // of the floor's irradiance
uniform float uAmbientFraction;
uniform float uStrength;            // settings x the character's opacity
uniform vec4 uContacts[8];          // x, z, disc radius, weight
uniform int uContactCount;
uniform vec3 uIrradianceSH[9];      // unused here; lighting.glsl declares irradiance() over it

float occludedShare(float height);

const float kContactOcclusion = 0.6;  // of the ambient light, at a contact's centre
const float kMaxDarkening = 0.95;
// 12 points spread over the unit disc (a Fibonacci spiral): the blocker search and the filter.
const vec2 kDisc[12] = vec2[12](
    vec2(0.204, 0.000), vec2(-0.261, 0.239), vec2(0.040, -0.455), vec2(0.329, 0.429),
    vec2(-0.603, -0.107), vec2(0.571, -0.363), vec2(-0.191, 0.711), vec2(-0.364, -0.702),
    vec2(0.791, 0.289), vec2(-0.822, 0.339), vec2(0.396, -0.847), vec2(0.293, 0.934));

float mapDepth(vec2 uv) {
  if (uv.x < 0.0 || uv.y < 0.0 || uv.x > 1.0 || uv.y > 1.0) return 1.0;
  return texture(uShadowMap, uv).r;
}

// The share of the directional light the caster blocks at this floor point, 0..1.
float directOcclusion() {
  vec4 clip = uLightViewProjection * vec4(vWorld, 1.0);
  vec2 uv = clip.xy * 0.5 + 0.5;
  float depth = clip.z * 0.5 + 0.5;
  float bias = 2.0 * uTexel;
  // Blockers within the widest penumbra this point can have; their mean depth sets its width.
  // Every other disc point: the search only needs their mean depth (6 taps, not 12).
  float search = clamp(uTanSoftness * depth, 2.0 * uTexel, 0.25);
  float blockers = 0.0, blockerDepth = 0.0;
  for (int i = 0; i < 12; i += 2) {
    float d = mapDepth(uv + kDisc[i] * search);
    if (d < 1.0 && d < depth - bias) {
      blockers += 1.0;
      blockerDepth += d;
    }
  }
  if (blockers == 0.0) return 0.0;
  blockerDepth /= blockers;
  float radius = max(uTanSoftness * (depth - blockerDepth), 1.5 * uTexel);
  float hidden = 0.0;
  for (int i = 0; i < 12; ++i) {
    float d = mapDepth(uv + kDisc[i] * radius);
    hidden += (d < 1.0 && d < depth - bias) ? 1.0 : 0.0;
  }
  return hidden / 12.0;
}

// The share of the ambient light the contacts block: the strongest disc here (soft, Gaussian).
float ambientOcclusion() {
  float occlusion = 0.0;
  for (int i = 0; i < 8; ++i) {
    if (i >= uContactCount) break;
    vec2 d = (vWorld.xz - uContacts[i].xy) / uContacts[i].z;
    occlusion = max(occlusion, uContacts[i].w * exp(-dot(d, d)));
  }
  return kContactOcclusion * occlusion;
}

void main() {
  float direct = uHasDirect != 0 ? directOcclusion() : 0.0;
  // A very low light's shadow is cut at the catcher's edge (3 bounding radii): faded, not clipped.
  float fade = 1.0 - smoothstep(0.8, 1.0, max(abs(vLocal.x), abs(vLocal.y)));
  // Where something real hides the floor (a hand), the floor's shadow is not seen.
  float lost = fade * (1.0 - occludedShare(0.0)) * uStrength * (uDirectFraction * direct + uAmbientFraction * ambientOcclusion());
  float kept = 1.0 - min(lost, kMaxDarkening);
  // The framebuffer holds display-referred values (about linear^(1/2.2)).
  fragColor = vec4(vec3(pow(kept, 1.0 / 2.2)), 1.0);
}
