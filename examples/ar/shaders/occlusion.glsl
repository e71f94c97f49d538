// Occlusion over the target (docs/ar-renderer.md, "Occlusion over the target"): where the
// tracker found the target hidden by something real (a hand), what is drawn over it is hidden
// too. The mask is in the camera frame's pixels (255 hidden, soft at its edges), so a fragment
// finds its value through the background's cover crop. Appended to every fragment shader;
// uOcclusionOn 0 costs one branch.
uniform sampler2D uOcclusionMask;   // R8, row 0 at the top of the frame
uniform int uOcclusionOn;
uniform vec4 uOcclusionScreenToImage;  // viewport [0, 1]^2 -> frame uv (origin bottom-left): coverRect
uniform vec2 uOcclusionImageToMask;    // frame uv (origin top-left) -> mask texture coordinates
uniform vec2 uOcclusionViewport;       // the viewport's size, pixels
uniform float uOcclusionHeight;        // metres above the floor: parts higher are in front (< 0: no limit)

// How much of this fragment the occluder hides, 0..1; `height` is its height above the floor.
float occludedShare(float height) {
  if (uOcclusionOn == 0) return 0.0;
  vec2 uv = gl_FragCoord.xy / uOcclusionViewport * uOcclusionScreenToImage.xy + uOcclusionScreenToImage.zw;
  float hidden = texture(uOcclusionMask, vec2(uv.x, 1.0 - uv.y) * uOcclusionImageToMask).r;
  // Above the occluder's height the part is in front of it; a soft band over its top fifth.
  if (uOcclusionHeight >= 0.0) hidden *= 1.0 - smoothstep(0.8 * uOcclusionHeight, uOcclusionHeight, height);
  return hidden;
}
