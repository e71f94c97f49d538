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

// Reinhard per channel, then the sRGB transfer curve.
vec3 toneMap(vec3 linear) {
  vec3 mapped = linear / (1.0 + linear);
  vec3 lo = mapped * 12.92;
  vec3 hi = 1.055 * pow(mapped, vec3(1.0 / 2.4)) - 0.055;
  return mix(lo, hi, step(vec3(0.0031308), mapped));
}
