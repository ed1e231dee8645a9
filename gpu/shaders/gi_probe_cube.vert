// Radiance probes (apps/gi, gpu/cube_raster.hpp): the mesh seen from a probe through one
// cube-map face. Clip coordinates (d.face_u, d.face_v, depth mapping, d.face_w) with
// d = position - probe: the window's (x, y) in [-1, 1]^2 are libsh's face coordinates
// (u, v) (atmosh/sh/projection.hpp), w is the depth along the face's axis.
layout(location = 0) in vec3 in_position;  // relative to the mesh's bounding-box centre
layout(location = 1) in vec3 in_normal;    // geometric normal of the surface (front = counter-clockwise)
layout(location = 2) in vec3 in_front;     // radiance leaving the front side
layout(location = 3) in vec3 in_back;      // radiance leaving the back side
uniform vec3 probe;                        // relative to the same centre
uniform vec3 face_u;
uniform vec3 face_v;
uniform vec3 face_w;
uniform float depth_a;
uniform float depth_b;
out vec3 v_d;
out vec3 v_normal;
out vec3 v_front;
out vec3 v_back;
void main() {
  vec3 d = in_position - probe;
  v_d = d;
  v_normal = in_normal;
  v_front = in_front;
  v_back = in_back;
  float w = dot(d, face_w);
  gl_Position = vec4(dot(d, face_u), dot(d, face_v), depth_a * w + depth_b, w);
}
