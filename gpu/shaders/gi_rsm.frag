// Reflective shadow map of a gi mesh from the sun (gpu/gi_raster.hpp): per texel the position
// (w = 1 marks a surface), the normal turned towards the sun and the flux its parallel beam
// leaves after one diffuse reflection: albedo x beam_flux (beam_flux = E_sun x the texel's
// cross-section).
in vec3 v_position;
flat in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec4 v_emission;
uniform vec3 sun_dir;    // towards the sun, unit
uniform vec3 beam_flux;  // per channel
layout(location = 0) out vec4 r_position;
layout(location = 1) out vec4 r_normal;
layout(location = 2) out vec4 r_flux;
void main() {
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0, 0.0, 1.0);
  if (dot(n, sun_dir) < 0.0) n = -n;
  r_position = vec4(v_position, 1.0);
  r_normal = vec4(n, 0.0);
  r_flux = vec4(v_albedo * beam_flux, 0.0);
}
