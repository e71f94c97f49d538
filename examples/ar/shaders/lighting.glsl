// Shared by the character and background shaders.

// E(n) = sum_i c_i Y_i(n) over the 9 real SH functions with +Y as the polar axis,
// in the order of marionette_ar/sh_lighting.hpp (index l (l + 1) + m).
vec3 irradiance(vec3 n) {
  vec3 e = uIrradianceSH[0] * 0.282095;
  e += uIrradianceSH[1] * (0.488603 * n.x);
  e += uIrradianceSH[2] * (0.488603 * n.y);
  e += uIrradianceSH[3] * (0.488603 * n.z);
  e += uIrradianceSH[4] * (1.092548 * n.x * n.z);
  e += uIrradianceSH[5] * (1.092548 * n.x * n.y);
  e += uIrradianceSH[6] * (0.315392 * (3.0 * n.y * n.y - 1.0));
  e += uIrradianceSH[7] * (1.092548 * n.y * n.z);
  e += uIrradianceSH[8] * (0.546274 * (n.z * n.z - n.x * n.x));
  return e;
}

// The sRGB transfer curve on values in 0..1.
vec3 encodeSrgb(vec3 v) {
  vec3 lo = v * 12.92;
  vec3 hi = 1.055 * pow(v, vec3(1.0 / 2.4)) - 0.055;
  return mix(lo, hi, step(vec3(0.0031308), v));
}

// Reinhard per channel, then the sRGB transfer curve.
vec3 toneMap(vec3 linear) { return encodeSrgb(linear / (1.0 + linear)); }

// A camera's curve: clipped at white, then sRGB. Light estimated from the camera is in the
// camera's linear values, so a character lit by it and drawn through this curve shows the
// brightness the camera would record for it.
vec3 cameraCurve(vec3 linear) { return encodeSrgb(clamp(linear, 0.0, 1.0)); }
