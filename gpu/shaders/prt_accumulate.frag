// Accumulation pass of the per-pixel transfer (gpu/prt.hpp): for one sample
// direction, each G-buffer pixel that sees the direction (depth-map test) adds
// max(0, n.w) Y_i(w) to channels first_channel .. first_channel + 4 TARGETS - 1
// (channel `coeffs` is the cosine sum for ambient occlusion). Additive blending.
// TARGETS is defined by the host.
layout(binding = 0) uniform sampler2D g_position;
layout(binding = 1) uniform sampler2D g_normal;
layout(binding = 2) uniform sampler2D depth_map;
layout(std430, binding = 0) readonly buffer SampleBasis { float ylm[]; };  // [s * coeffs + i]
uniform mat4 light_proj;     // centred mesh frame -> clip space of the depth map
uniform vec3 direction;      // unit sample direction (towards the light)
uniform int basis_offset;    // s * coeffs
uniform int coeffs;          // bands^2
uniform int first_channel;   // first channel of this pass
uniform int visibility;      // 0: no depth test (unshadowed)
uniform float normal_offset; // [mesh units]
uniform float depth_bias;    // constant, [depth units]
uniform float slope_bias;    // per unit tan(angle), [depth units]
layout(location = 0) out vec4 acc[TARGETS];

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 p = texelFetch(g_position, px, 0);
  if (p.w == 0.0) discard;
  vec3 n = texelFetch(g_normal, px, 0).xyz;
  float c = dot(n, direction);
  if (c <= 0.0) discard;
  if (visibility != 0) {
    vec3 q = p.xyz + n * normal_offset;
    vec3 uvz = (light_proj * vec4(q, 1.0)).xyz * 0.5 + 0.5;
    float tan_angle = min(sqrt(max(1.0 - c * c, 0.0)) / c, 8.0);
    float stored = texture(depth_map, uvz.xy).r;
    if (uvz.z > stored + depth_bias + slope_bias * tan_angle) discard;
  }
  for (int t = 0; t < TARGETS; ++t) {
    vec4 v = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
      int ch = first_channel + 4 * t + k;
      v[k] = ch < coeffs ? c * ylm[basis_offset + ch] : (ch == coeffs ? c : 0.0);
    }
    acc[t] = v;
  }
}
