// One propagation iteration of a light propagation volume (the GPU form of lpv_step in
// apps/gi/src/lpv.cpp, the same math; atmosh/gi/lpv.hpp describes it): every target cell
// gathers, from each of its 6 face neighbours, the flux through its 5 faces other than the
// shared one, dOmega_f I(w_f) (1 - B), re-emitted as a Lambertian lobe about the face normal;
// the new field goes to `dst` and is added to the running sum `acc`.
// Cells: 12 floats each (3 channels x SH bands 0-1, index l(l+1)+m), index (k ny + j) nx + i.
// vis: 1 - blocking per (cell, direction, face), [(t 6 + d) 5 + f], used when use_vis != 0.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Src { float src[]; };
layout(std430, binding = 1) readonly buffer Vis { float vis[]; };
layout(std430, binding = 2) writeonly buffer Dst { float dst[]; };
layout(std430, binding = 3) buffer Acc { float acc[]; };
uniform int nx;
uniform int ny;
uniform int nz;
uniform int use_vis;

const float kY00 = 0.28209479177387814;  // 1 / (2 sqrt(pi))
const float kY1 = 0.48860251190291992;   // sqrt(3 / (4 pi))

vec4 sh4(vec3 d) { return vec4(kY00, -kY1 * d.y, kY1 * d.z, -kY1 * d.x); }

void main() {
  int t = int(gl_GlobalInvocationID.x);
  if (t >= nx * ny * nz) return;
  ivec3 c = ivec3(t % nx, (t / nx) % ny, t / (nx * ny));
  // The exact solid angles of the far face and of a side face (docs/gi.md).
  float front = 4.0 * asin(0.1);
  float side = 2.0 * (atan(3.0 / sqrt(11.0)) - 3.14159265358979324 / 6.0);
  vec4 out0 = vec4(0.0), out1 = vec4(0.0), out2 = vec4(0.0);
  for (int d = 0; d < 6; ++d) {  // the CPU's order: axis 0..2, sign +1 then -1
    int axis = d / 2;
    int sgn = (d % 2 == 0) ? 1 : -1;
    ivec3 e = ivec3(0);
    e[axis] = sgn;
    ivec3 s = c - e;
    if (any(lessThan(s, ivec3(0))) || any(greaterThanEqual(s, ivec3(nx, ny, nz)))) continue;
    int si = (s.z * ny + s.y) * nx + s.x;
    vec4 c0 = vec4(src[si * 12 + 0], src[si * 12 + 1], src[si * 12 + 2], src[si * 12 + 3]);
    vec4 c1 = vec4(src[si * 12 + 4], src[si * 12 + 5], src[si * 12 + 6], src[si * 12 + 7]);
    vec4 c2 = vec4(src[si * 12 + 8], src[si * 12 + 9], src[si * 12 + 10], src[si * 12 + 11]);
    if (c0 == vec4(0.0) && c1 == vec4(0.0) && c2 == vec4(0.0)) continue;
    for (int f = 0; f < 5; ++f) {
      vec3 nf = vec3(e);
      vec3 dir = vec3(e);
      float om = front;
      if (f > 0) {  // side faces: the other axes in increasing order, sign +1 then -1
        int idx = f - 1;
        int other = (idx / 2 == 0) ? (axis == 0 ? 1 : 0) : (axis == 2 ? 1 : 2);
        nf = vec3(0.0);
        nf[other] = (idx % 2 == 0) ? 1.0 : -1.0;
        dir = normalize(vec3(e) + 0.5 * nf);
        om = side;
      }
      float v = use_vis != 0 ? vis[(t * 6 + d) * 5 + f] : 1.0;
      if (v <= 0.0) continue;
      vec4 y = sh4(dir);
      vec4 lobe = sh4(nf) * vec4(1.0, 2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0);
      out0 += om * dot(c0, y) * v * lobe;
      out1 += om * dot(c1, y) * v * lobe;
      out2 += om * dot(c2, y) * v * lobe;
    }
  }
  for (int q = 0; q < 4; ++q) {
    dst[t * 12 + q] = out0[q];
    dst[t * 12 + 4 + q] = out1[q];
    dst[t * 12 + 8 + q] = out2[q];
    acc[t * 12 + q] += out0[q];
    acc[t * 12 + 4 + q] += out1[q];
    acc[t * 12 + 8 + q] += out2[q];
  }
}
