// Sun-table lookups for a list of origins (gpu::sun_lookups): sky_lib.glsl's
// sun_lookup, the code the sky pass evaluates at each of its integration nodes.
// Input dirs[i] = (altitude [m], cosine of the sun's zenith angle, -, -); output
// radiance[4 i + c] = column c [m] (0 Rayleigh, 1 Mie, 2 ozone) to the top of the
// atmosphere, radiance[4 i + 3] = 1 where the ground blocks the ray. Assembled after
// sky_lib.glsl.
layout(local_size_x = ATMOSH_ITEM_GROUP_SIZE) in;


void main() {
  int i = item_index(int(gl_GlobalInvocationID.x), int(gl_GlobalInvocationID.y), int(gl_NumWorkGroups.x));
  if (i >= params.n_items) return;
  vec4 c = sun_lookup(dirs[i].x, dirs[i].y);
  for (int k = 0; k < 4; ++k) radiance[4 * i + k] = c[k];
}
