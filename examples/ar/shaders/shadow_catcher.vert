// The shadow catcher: a rectangle on the floor (y = 0) under one character, along where its
// shadow falls, drawn as a four-vertex triangle strip whose corners come from gl_VertexID.
uniform vec4 uCatcherCentre;    // centre x, z; long axis x, z (unit)
uniform vec4 uCatcherHalfSize;  // half length along the axis, half width across (metres)
uniform mat4 uViewProjection;
out vec3 vWorld;
out vec2 vLocal;  // -1..1 along and across

void main() {
  vLocal = vec2(float((gl_VertexID & 1) * 2 - 1), float((gl_VertexID >> 1) * 2 - 1));
  vec2 axis = uCatcherCentre.zw, across = vec2(-axis.y, axis.x);
  vec2 p = uCatcherCentre.xy + axis * (vLocal.x * uCatcherHalfSize.x) + across * (vLocal.y * uCatcherHalfSize.y);
  vWorld = vec3(p.x, 0.0, p.y);
  gl_Position = uViewProjection * vec4(vWorld, 1.0);
}
