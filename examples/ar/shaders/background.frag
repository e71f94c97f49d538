// Background: a camera frame (photo, image sequence or video), fitted to cover
// the viewport, or the HDR environment seen through the camera (tone-mapped
// with the same exposure as the characters).
in vec2 vScreen;
out vec4 fragColor;

uniform int uMode;               // 0: camera image; 1: environment; 2: flat colour
uniform sampler2D uImage;        // display-referred RGB, row 0 at the top
uniform vec4 uImageRect;         // xy scale, zw offset: screen -> image coordinates
uniform sampler2D uEnvironment;  // linear RGB lat-long, row 0 at +Y
uniform mat4 uInverseViewProjection;
uniform float uExposure;
uniform float uEnvironmentRotation;  // radians about +Y
uniform vec3 uFlatColor;
uniform vec3 uIrradianceSH[9];  // unused here; lighting.glsl declares irradiance() over it

vec3 toneMap(vec3 linear);
vec3 irradiance(vec3 n);

void main() {
  if (uMode == 0) {
    vec2 uv = vScreen * uImageRect.xy + uImageRect.zw;
    fragColor = vec4(texture(uImage, vec2(uv.x, 1.0 - uv.y)).rgb, 1.0);
  } else if (uMode == 1) {
    vec4 far = uInverseViewProjection * vec4(vScreen * 2.0 - 1.0, 1.0, 1.0);
    vec4 near = uInverseViewProjection * vec4(vScreen * 2.0 - 1.0, -1.0, 1.0);
    vec3 d = normalize(far.xyz / far.w - near.xyz / near.w);
    float c = cos(uEnvironmentRotation), s = sin(uEnvironmentRotation);
    d = vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);  // into the map's frame
    // Map convention (marionette_ar/environment_map.hpp): u = atan(x, -z) / 2pi + 0.5, v = acos(y) / pi.
    vec2 uv = vec2(atan(d.x, -d.z) / 6.2831853 + 0.5, acos(clamp(d.y, -1.0, 1.0)) / 3.14159265);
    fragColor = vec4(toneMap(texture(uEnvironment, uv).rgb * uExposure), 1.0);
  } else {
    fragColor = vec4(uFlatColor, 1.0);
  }
}
