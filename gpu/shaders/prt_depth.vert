// Depth map along one sample direction: orthographic projection of the mesh.
layout(location = 0) in vec3 in_position;
uniform mat4 light_proj;
void main() { gl_Position = light_proj * vec4(in_position, 1.0); }
