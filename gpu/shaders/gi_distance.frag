// Distance cube-map face of an area-light sample point (gpu/gi_raster.hpp): the distance from
// `origin` to the nearest surface (the depth test keeps the nearest).
in vec3 v_position;
flat in vec3 v_normal;
flat in vec3 v_albedo;
flat in vec4 v_emission;
uniform vec3 origin;
layout(location = 0) out float distance_out;
void main() { distance_out = length(v_position - origin); }
