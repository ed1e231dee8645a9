// The volume fetches that the shared block of atmosh/gi/shared/radiosity.glsl.hpp declares
// for its walk (gi_radiosity_incident); the probe frame (gi_probe_shade.frag) uses only the
// block's gi_sh_irradiance, so these are never called.
float gi_fetch_distance(vec3 p, vec3 d) { return 0.0; }
vec3 gi_fetch_normal(vec3 q) { return vec3(0.0); }
vec3 gi_fetch_albedo(vec3 q) { return vec3(0.0); }
vec3 gi_direct_irradiance(vec3 q, vec3 n) { return vec3(0.0); }
// The block's C++ context parameter is empty in GLSL (see the header's comment).
#define ATMOSH_GI_TEMPLATE
#define ATMOSH_GI_CTX
#define ATMOSH_GI_CTX_ARG
