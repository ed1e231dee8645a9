// Radiance probes: the sun's direct light in the probe frame (gi_probe_shade.frag), by the
// sun's shadow map of gpu/gi_raster.hpp (the same map and test as its G-buffer,
// gi_gbuffer.frag: orthographic depth along -s over the bounding sphere; the receiver moved
// `sun_normal_offset` texels along n, its depth against the stored depth + `sun_bias` texels
// x (1 + min(tan, 8)), over the (2 pcf + 1)^2 texels around it, averaged).
// probe_sun_factor(p, n) = max(0, n . s) V(p) in [0, 1]; 0 without a sun.
uniform int has_sun;
uniform vec3 sun_dir;              // towards the sun, unit
uniform vec3 sun_irradiance;       // at normal incidence, per channel
uniform mat4 sun_light_proj;       // orthographic along -sun_dir over the bounding sphere
uniform sampler2D sun_shadow_map;  // depth, nearest
uniform int sun_shadow_res;
uniform float sun_texel;           // texel edge [mesh units]
uniform float sun_radius;          // bounding-sphere radius: depth units are 1 / (2 radius)
uniform float sun_normal_offset;   // texels
uniform float sun_bias;            // texels
uniform int sun_pcf;

float probe_sun_factor(vec3 p, vec3 n) {
  if (has_sun == 0) return 0.0;
  float c = dot(n, sun_dir);
  if (c <= 0.0) return 0.0;
  vec3 q = p + n * (sun_normal_offset * sun_texel);
  vec4 lp = sun_light_proj * vec4(q, 1.0);
  vec2 uv = lp.xy * 0.5 + 0.5;
  float d = lp.z * 0.5 + 0.5;
  float slope = min(sqrt(max(0.0, 1.0 - c * c)) / c, 8.0);
  float db = sun_bias * sun_texel * (1.0 + slope) / (2.0 * sun_radius);
  ivec2 base = ivec2(floor(uv * float(sun_shadow_res)));
  float lit = 0.0;
  float count = 0.0;
  for (int dy = -sun_pcf; dy <= sun_pcf; ++dy)
    for (int dx = -sun_pcf; dx <= sun_pcf; ++dx) {
      ivec2 tc = clamp(base + ivec2(dx, dy), ivec2(0), ivec2(sun_shadow_res - 1));
      lit += d <= texelFetch(sun_shadow_map, tc, 0).r + db ? 1.0 : 0.0;
      count += 1.0;
    }
  return c * lit / count;
}
