// The surface point seen at this fragment's pixel centre (atmosh/gpu/pixel_ray.hpp): the
// camera ray through gl_FragCoord.xy intersected with the plane of the fragment's triangle
// (normal n, any length; a: one of its vertices), relative to the same centre as `eye_`.
// A perspective-interpolated position carries the rasteriser's attribute error, which differs
// between drivers (docs/gi.md, "The surface point of a pixel"); the plane intersection is
// float-exact wherever the ray meets the plane at more than 0.06 degrees. At a shallower angle,
// and for a degenerate normal, it returns the interpolated `p`.
uniform vec3 pixel_ray[3];
vec3 gi_pixel_point(vec3 eye_, vec3 p, vec3 n, vec3 a) {
  vec3 d = pixel_ray[0] + gl_FragCoord.x * pixel_ray[1] + gl_FragCoord.y * pixel_ray[2];
  float dn = dot(n, d);
  if (!(abs(dn) > 1e-3 * length(n) * length(d))) return p;
  return eye_ + (dot(n, a - eye_) / dn) * d;
}
