// Shadow map pass (character.vert from the light): only the depth is kept; alpha-tested
// cut-outs (eyelashes, hair cards) cast no shadow, as they show no surface.
in vec3 vNormal;
in vec2 vUv;
in vec3 vPrtIrradiance;
out vec4 fragColor;

uniform vec4 uBaseColor;
uniform sampler2D uBaseColorTexture;
uniform int uHasTexture;
uniform vec3 uIrradianceSH[9];  // unused here; lighting.glsl declares irradiance() over it

void main() {
  float alpha = uBaseColor.a;
  if (uHasTexture != 0) alpha *= texture(uBaseColorTexture, vUv).a;
  if (alpha < 0.5) discard;
  fragColor = vec4(1.0);
}
