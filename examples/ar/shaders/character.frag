// Character fragment shader: diffuse irradiance, either per vertex from PRT
// (uPrt: the CPU relit each vertex's transfer, self-shadowing included) or per
// fragment from 9 SH coefficients of the environment (Ramamoorthi & Hanrahan
// 2001), times the base colour and its texture, times exposure, then tone mapping
// to display sRGB.
in vec3 vNormal;
in vec2 vUv;
in vec3 vPrtIrradiance;
in vec3 vWorld;
out vec4 fragColor;

uniform vec3 uIrradianceSH[9];  // E(n) = sum_i c_i Y_i(n), linear RGB
uniform vec4 uBaseColor;
uniform sampler2D uBaseColorTexture;
uniform int uHasTexture;
uniform float uExposure;
uniform int uPrt;         // 1: vPrtIrradiance is the irradiance
uniform int uOutputMode;  // 0: lit; 1: unlit base colour (tests); 2: normals (tests)
uniform float uOpacity;   // < 1 while the camera's pose is less certain (blended over the background)
                          // (and faded where something real hides the target: occlusion.glsl)
uniform int uCameraCurve; // 1: the light is the camera's estimate: its curve, not the tone map

vec3 irradiance(vec3 n);
vec3 toneMap(vec3 linear);
vec3 cameraCurve(vec3 linear);
float occludedShare(float height);

void main() {
  vec3 n = normalize(vNormal);
  if (!gl_FrontFacing) n = -n;  // thin two-sided parts (hair, cloth) light from the side seen
  vec4 base = uBaseColor;
  if (uHasTexture != 0) base *= texture(uBaseColorTexture, vUv);
  if (base.a < 0.5) discard;  // alpha-tested cut-outs (eyelashes, hair cards)
  if (uOutputMode == 1) { fragColor = vec4(base.rgb, 1.0); return; }
  if (uOutputMode == 2) { fragColor = vec4(0.5 * n + 0.5, 1.0); return; }
  // A back face has no transfer of its own (the vertex's is its front's, facing away): it
  // keeps the SH9 light of the side seen (thin parts; cracks between meshes show no bright seam).
  vec3 e = uPrt != 0 && gl_FrontFacing ? vPrtIrradiance : irradiance(n);
  vec3 radiance = base.rgb / 3.14159265 * max(e, vec3(0.0));
  vec3 exposed = radiance * uExposure;
  float alpha = uOpacity * (1.0 - occludedShare(vWorld.y));
  fragColor = vec4(uCameraCurve != 0 ? cameraCurve(exposed) : toneMap(exposed), alpha);
}
