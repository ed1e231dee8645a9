// G-buffer of a gi mesh from the camera (gpu/gi_raster.hpp): position (w = 1 marks a
// surface), the normal turned towards the eye (w: the sun factor max(0, n . s) V), albedo,
// emitted radiance towards the eye. V by the sun's shadow map: the point moved `normal_offset`
// texels along n, its depth against the stored depth + `bias` texels x (1 + min(tan, 8)), over
// the (2 pcf + 1)^2 texels around it (percentage-closer filtering).
in vec3 v_position;
flat in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec4 v_emission;
uniform vec3 eye;             // relative to the bounding-box centre
uniform int has_sun;
uniform vec3 sun_dir;         // towards the sun, unit
uniform mat4 light_proj;      // orthographic along -sun_dir over the bounding sphere
uniform sampler2D shadow_map; // depth, nearest
uniform int shadow_res;
uniform float texel;          // shadow-map texel edge [mesh units]
uniform float radius;         // bounding-sphere radius: depth units are 1 / (2 radius)
uniform float normal_offset;  // texels
uniform float bias;           // texels
uniform int pcf;
layout(location = 0) out vec4 g_position;
layout(location = 1) out vec4 g_normal;
layout(location = 2) out vec4 g_albedo;
layout(location = 3) out vec4 g_emission;
void main() {
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0, 0.0, 1.0);
  bool front = dot(n, eye - v_position) > 0.0;
  if (!front) n = -n;
  vec3 e = (v_emission.w > 0.5 && !front) ? vec3(0.0) : v_emission.rgb;
  float f = 0.0;
  if (has_sun != 0) {
    float c = dot(n, sun_dir);
    if (c > 0.0) {
      vec3 q = v_position + n * (normal_offset * texel);
      vec4 lp = light_proj * vec4(q, 1.0);
      vec2 uv = lp.xy * 0.5 + 0.5;
      float d = lp.z * 0.5 + 0.5;
      float slope = min(sqrt(max(0.0, 1.0 - c * c)) / c, 8.0);
      float db = bias * texel * (1.0 + slope) / (2.0 * radius);
      ivec2 base = ivec2(floor(uv * float(shadow_res)));
      float lit = 0.0;
      float count = 0.0;
      for (int dy = -pcf; dy <= pcf; ++dy)
        for (int dx = -pcf; dx <= pcf; ++dx) {
          ivec2 tc = clamp(base + ivec2(dx, dy), ivec2(0), ivec2(shadow_res - 1));
          float stored = texelFetch(shadow_map, tc, 0).r;
          lit += d <= stored + db ? 1.0 : 0.0;
          count += 1.0;
        }
      f = c * lit / count;
    }
  }
  g_position = vec4(v_position, 1.0);
  g_normal = vec4(n, f);
  g_albedo = vec4(v_albedo, 1.0);
  g_emission = vec4(e, 1.0);
}
