// Declarations that come before the shared blocks of atmosh/gi/shared/radiosity.glsl.hpp and
// atmosh/gi/shared/lpv.glsl.hpp in the LPV shaders (gi_lpv_*): the blocks' C++ context
// parameter is empty in GLSL, real4 is vec4, the radiosity walk's volume fetches are stubs
// (the LPV uses only that block's gi_sh_eval and gi_sh_irradiance), and the LPV block's three
// fetches are declared here and defined by each shader (those it does not use return a constant);
// the per-face constants of the gather (gi_lpv_face_y, gi_lpv_face_reemit) are defined here from
// the block's functions (declared here, defined by the block); the re-emission is chosen by the
// uniform lpv_reemission (0 the default, 1 Kaplanyan & Dachsbacher 2010's face-normal lobe;
// atmosh/gi/lpv.hpp, LpvReemission; 0 unless set: uniforms start at 0 at link).
#define ATMOSH_GI_TEMPLATE
#define ATMOSH_GI_CTX
#define ATMOSH_GI_CTX_ARG
#define real4 vec4
float gi_fetch_distance(vec3 p, vec3 d) { return 0.0; }
vec3 gi_fetch_normal(vec3 q) { return vec3(0.0); }
vec3 gi_fetch_albedo(vec3 q) { return vec3(0.0); }
vec3 gi_direct_irradiance(vec3 q, vec3 n) { return vec3(0.0); }
vec4 gi_lpv_fetch(ivec3 s, int ch);
float gi_lpv_open(ivec3 t, ivec3 s, int d, int f);
float gi_lpv_fetch_corner(int c, int q);
vec4 gi_lpv_sh4(vec3 d);
vec4 gi_lpv_lobe(vec3 n);
vec3 gi_lpv_face_normal(int d, int f);
vec3 gi_lpv_face_direction(int d, int f);
vec4 gi_lpv_reemit_sh(int d, int f);
vec4 gi_lpv_reemit_choice(int reemission, int d, int f);
uniform int lpv_reemission;
vec4 gi_lpv_face_y(int d, int f) { return gi_lpv_sh4(gi_lpv_face_direction(d, f)); }
vec4 gi_lpv_face_reemit(int d, int f) { return gi_lpv_reemit_choice(lpv_reemission, d, f); }
