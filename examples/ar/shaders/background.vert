// Full-screen triangle; the fragment shader draws the camera image or the environment.
out vec2 vScreen;  // 0..1, origin bottom-left

void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  vScreen = corner;
  gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
}
