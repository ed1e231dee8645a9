// G-buffer of a gi mesh from the camera (gpu/gi_raster.hpp): position (w = 1 marks a
// surface), the normal turned towards the eye (w: the sun factor max(0, n . s) V), albedo,
// emitted radiance towards the eye. V by the sun's shadow map: the point moved `normal_offset`
// texels along n, its depth against the stored depth + `bias` texels x (1 + min(tan, 8)), over
// the (2 pcf + 1)^2 texels around it (percentage-closer filtering). Area emitters (target 4):
// each emitting triangle's unoccluded irradiance (gi_polygon_irradiance, the shared block
// pasted before this file) times the mean visibility of its sample points, each by its
// distance cube map (six faces per point in a 2D array texture, layer 6 k + face).
in vec3 v_position;
flat in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec4 v_emission;
flat in vec3 v_anchor;
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
layout(location = 4) out vec4 g_emitter;
layout(location = 5) out vec4 g_sky;
// Sky directions: 12 floats each (direction w, the depth map's axes ex, ey, L x weight).
layout(std430, binding = 2) readonly buffer GiSky { float sk[]; };
uniform int n_sky;
uniform int sky_res;
uniform sampler2DArray sky_maps;
// Emitting triangles: 16 floats each (v0, v1, v2, radiance, unit normal, one-sided flag),
// positions relative to the bounding-box centre; their points: 4 floats each, triangle e's
// at e points_per_tri ... (e + 1) points_per_tri - 1.
layout(std430, binding = 0) readonly buffer GiEmitters { float em[]; };
layout(std430, binding = 1) readonly buffer GiEmitterPoints { float ep[]; };
uniform int n_emitters;
uniform int points_per_tri;
uniform sampler2DArray emitter_maps;
uniform int emitter_res;
uniform float eval_offset;    // the polygon formula's evaluation height above p
uniform float shadow_offset;  // the visibility test's origin height above p
uniform vec3 face_f[6];
uniform vec3 face_r[6];
uniform vec3 face_u[6];

vec3 sk3(int k, int o) { return vec3(sk[k * 12 + o], sk[k * 12 + o + 1], sk[k * 12 + o + 2]); }

// The environment through the sky directions' depth maps (one tap each).
vec3 sky_irradiance(vec3 p, vec3 n) {
  vec3 E = vec3(0.0);
  float tex_s = 2.0 * radius / float(sky_res);
  for (int k = 0; k < n_sky; ++k) {
    vec3 w = sk3(k, 0);
    float c = dot(n, w);
    if (c <= 0.0) continue;
    vec3 q = p + n * (normal_offset * tex_s);
    vec2 uv = vec2(dot(q, sk3(k, 3)), dot(q, sk3(k, 6))) / radius * 0.5 + 0.5;
    float d = -dot(q, w) / radius * 0.5 + 0.5;
    float slope = min(sqrt(max(0.0, 1.0 - c * c)) / c, 8.0);
    float db = bias * tex_s * (1.0 + slope) / (2.0 * radius);
    ivec2 tc = clamp(ivec2(floor(uv * float(sky_res))), ivec2(0), ivec2(sky_res - 1));
    if (d <= texelFetch(sky_maps, ivec3(tc, k), 0).r + db) E += sk3(k, 9) * c;
  }
  return E;
}

vec3 em3(int e, int o) { return vec3(em[e * 16 + o], em[e * 16 + o + 1], em[e * 16 + o + 2]); }

// Visibility of point k from q (normal n) by its distance cube map.
float point_visible(int k, vec3 q, vec3 n) {
  vec3 y = vec3(ep[k * 4], ep[k * 4 + 1], ep[k * 4 + 2]);
  vec3 d = q - y;
  vec3 ad = abs(d);
  int f;
  if (ad.x >= ad.y && ad.x >= ad.z)
    f = d.x > 0.0 ? 0 : 1;
  else if (ad.y >= ad.z)
    f = d.y > 0.0 ? 2 : 3;
  else
    f = d.z > 0.0 ? 4 : 5;
  float w = dot(d, face_f[f]);
  vec2 uv = vec2(dot(d, face_r[f]), dot(d, face_u[f])) / w;
  ivec2 tc = clamp(ivec2(floor((uv * 0.5 + 0.5) * float(emitter_res))), ivec2(0), ivec2(emitter_res - 1));
  float stored = texelFetch(emitter_maps, ivec3(tc, k * 6 + f), 0).r;
  float dist = length(d);
  float c = max(dot(n, -d) / max(dist, 1e-30), 1e-3);
  float slope = min(sqrt(max(0.0, 1.0 - c * c)) / c, 8.0);
  float bias = 1.5 * dist * (2.0 / float(emitter_res)) * (1.0 + slope);
  return dist <= stored + bias ? 1.0 : 0.0;
}
void main() {
  float len = length(v_normal);
  vec3 n = len > 0.0 ? v_normal / len : vec3(0.0, 0.0, 1.0);
  // The point at the pixel centre (gi_pixel_point.glsl, pasted before this file).
  vec3 pos = gi_pixel_point(eye, v_position, n, v_anchor);
  bool front = dot(n, eye - pos) > 0.0;
  if (!front) n = -n;
  vec3 e = (v_emission.w > 0.5 && !front) ? vec3(0.0) : v_emission.rgb;
  float f = 0.0;
  if (has_sun != 0) {
    float c = dot(n, sun_dir);
    if (c > 0.0) {
      vec3 q = pos + n * (normal_offset * texel);
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
  vec3 Eem = vec3(0.0);
  for (int t = 0; t < n_emitters; ++t) {
    vec3 v0 = em3(t, 0), v1 = em3(t, 3), v2 = em3(t, 6), L = em3(t, 9), en = em3(t, 12);
    if (em[t * 16 + 15] > 0.5 && dot(en, pos - v0) <= 0.0) continue;  // behind a one-sided emitter
    float F = gi_polygon_irradiance(pos + eval_offset * n, n, v0, v1, v2);
    if (!(F > 0.0)) continue;
    vec3 q = pos + shadow_offset * n;
    float vis = 0.0;
    for (int k = 0; k < points_per_tri; ++k) vis += point_visible(t * points_per_tri + k, q, n);
    Eem += L * (F * vis / float(points_per_tri));
  }
  g_emitter = vec4(Eem, 1.0);
  g_sky = vec4(n_sky > 0 ? sky_irradiance(pos, n) : vec3(0.0), 1.0);
  g_position = vec4(pos, 1.0);
  g_normal = vec4(n, f);
  g_albedo = vec4(v_albedo, 1.0);
  g_emission = vec4(e, 1.0);
}
