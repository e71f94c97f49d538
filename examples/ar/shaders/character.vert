// Character vertex shader: morph targets, then linear-blend skinning from the
// bridge's packed 3x4 palette, then the character's world matrix.
// Written once for GLSL 3.30 core and GLSL ES 3.00 (the loader prepends the
// #version line and, for ES, the precision statements).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in vec4 aJoints;   // joint indices as floats (exact below 2^24)
layout(location = 4) in vec4 aWeights;
layout(location = 5) in vec3 aPrtIrradiance;  // PRT: E_v relit on the CPU each frame (uPrt)

// Three RGBA32F texels per joint (one row each of the 3x4 skinning matrix),
// joint j on texture row j: a texture, not a uniform array, so that skeletons
// of any size fit the 1024 uniform components GL 3.3 and ES 3.0 guarantee.
uniform sampler2D uPalette;
uniform int uSkinned;          // 0: rigid mesh, uRigid places it
uniform mat4 uRigid;           // model-space matrix of a rigid mesh
uniform mat4 uWorld;           // world-from-model of the character
uniform mat4 uViewProjection;

// Morph deltas: texel i = morph * vertexCount + vertex, row-major in a
// uMorphTextureWidth-wide RGBA32F texture; only the active morphs are summed.
const int kMaxActiveMorphs = 8;
uniform sampler2D uMorphPositions;
uniform sampler2D uMorphNormals;
uniform int uMorphTextureWidth;
uniform int uVertexCount;
uniform int uActiveMorphs;
uniform int uMorphIndex[kMaxActiveMorphs];
uniform float uMorphWeight[kMaxActiveMorphs];

out vec3 vNormal;
out vec2 vUv;
out vec3 vPrtIrradiance;
out vec3 vWorld;  // occlusion.glsl's height above the floor

ivec2 morphTexel(int morph) {
  int i = morph * uVertexCount + gl_VertexID;
  return ivec2(i % uMorphTextureWidth, i / uMorphTextureWidth);
}

mat4 paletteMatrix(float joint) {
  int j = int(joint + 0.5);
  vec4 r0 = texelFetch(uPalette, ivec2(0, j), 0);
  vec4 r1 = texelFetch(uPalette, ivec2(1, j), 0);
  vec4 r2 = texelFetch(uPalette, ivec2(2, j), 0);
  // GLSL matrices are built column by column: transpose the rows.
  return mat4(vec4(r0.x, r1.x, r2.x, 0.0), vec4(r0.y, r1.y, r2.y, 0.0),
              vec4(r0.z, r1.z, r2.z, 0.0), vec4(r0.w, r1.w, r2.w, 1.0));
}

void main() {
  vec3 position = aPosition;
  vec3 normal = aNormal;
  for (int k = 0; k < kMaxActiveMorphs; ++k) {
    if (k >= uActiveMorphs) break;
    ivec2 t = morphTexel(uMorphIndex[k]);
    position += uMorphWeight[k] * texelFetch(uMorphPositions, t, 0).xyz;
    normal += uMorphWeight[k] * texelFetch(uMorphNormals, t, 0).xyz;
  }
  mat4 skin = uRigid;
  if (uSkinned != 0) {
    skin = aWeights.x * paletteMatrix(aJoints.x) + aWeights.y * paletteMatrix(aJoints.y) +
           aWeights.z * paletteMatrix(aJoints.z) + aWeights.w * paletteMatrix(aJoints.w);
  }
  mat4 model = uWorld * skin;
  vec4 world = model * vec4(position, 1.0);
  // Inverse transpose for non-uniform scale; skinning matrices are near-rigid.
  vNormal = mat3(model) * normal;
  vUv = aUv;
  vPrtIrradiance = aPrtIrradiance;
  vWorld = world.xyz;
  gl_Position = uViewProjection * world;
}
