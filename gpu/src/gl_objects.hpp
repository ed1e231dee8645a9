// Private helpers of the rasterisation passes (prt.cpp, gi_raster.cpp): GL names held by
// RAII, a column-major matrix for uniforms, 2D texture storage, the framebuffer check and
// a program's one-source parts. Include after <GL/glcorearb.h>.
#pragma once

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/gpu/program.hpp"

namespace atmosh::gpu::detail {

// Column-major 4x4 from rows (row r, column c -> m[c * 4 + r]).
struct Mat4 {
  float m[16] = {};
  void set(int r, int c, double v) { m[c * 4 + r] = static_cast<float>(v); }
};

// RAII holder of n GL names made by Gen and released by Del.
template <void (*Gen)(GLsizei, GLuint*), void (*Del)(GLsizei, const GLuint*)>
struct GlNames {
  std::vector<GLuint> ids;
  explicit GlNames(std::size_t n) : ids(n, 0) {
    if (n) Gen(static_cast<GLsizei>(n), ids.data());
  }
  ~GlNames() {
    if (!ids.empty()) Del(static_cast<GLsizei>(ids.size()), ids.data());
  }
  GlNames(const GlNames&) = delete;
  GlNames& operator=(const GlNames&) = delete;
};
using Textures = GlNames<glGenTextures, glDeleteTextures>;
using Framebuffers = GlNames<glGenFramebuffers, glDeleteFramebuffers>;
using GlBuffers = GlNames<glGenBuffers, glDeleteBuffers>;
using VertexArrays = GlNames<glGenVertexArrays, glDeleteVertexArrays>;

// Orthographic projection along -s (s a unit vector towards the light) over a bounding
// sphere of `radius` about the origin: x, y on axes ex, ey / radius, depth (radius - p.s) /
// (2 radius), nearest to the light first (the depth maps of prt.cpp and gi_raster.cpp).
inline Mat4 light_matrix(const glm::dvec3& s, double radius) {
  const glm::dvec3 ex = glm::normalize(std::abs(s.z) < 0.9 ? glm::cross(glm::dvec3(0, 0, 1), s)
                                                           : glm::cross(glm::dvec3(1, 0, 0), s));
  const glm::dvec3 ey = glm::cross(s, ex);
  Mat4 lp;
  for (int c = 0; c < 3; ++c) {
    lp.set(0, c, ex[c] / radius);
    lp.set(1, c, ey[c] / radius);
    lp.set(2, c, -s[c] / radius);
  }
  lp.set(3, 3, 1.0);
  return lp;
}

// Perspective view-projection of a camera at `eye` with unit axes right, up, back (looking
// along -back), tan of half the vertical field of view, a W x H image and depth range
// [near_d, far_d] (OpenGL clip space; the PRT and gi G-buffer passes).
inline Mat4 camera_matrix(const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& back, double tan_half_fov,
                          const glm::dvec3& eye, int W, int H, double near_d, double far_d) {
  const double aspect = static_cast<double>(W) / H, th = tan_half_fov;
  const double sx = 1.0 / (th * aspect), sy = 1.0 / th;
  const double a = -(far_d + near_d) / (far_d - near_d), b = -2.0 * far_d * near_d / (far_d - near_d);
  Mat4 vp;
  for (int c = 0; c < 3; ++c) {
    vp.set(0, c, sx * right[c]);
    vp.set(1, c, sy * up[c]);
    vp.set(2, c, a * back[c]);
    vp.set(3, c, -back[c]);
  }
  vp.set(0, 3, -sx * glm::dot(right, eye));
  vp.set(1, 3, -sy * glm::dot(up, eye));
  vp.set(2, 3, -a * glm::dot(back, eye) + b);
  vp.set(3, 3, glm::dot(back, eye));
  return vp;
}

// One level of `format`, nearest filtering, clamped to the edge.
inline void storage_2d(GLuint tex, GLenum format, int w, int h) {
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexStorage2D(GL_TEXTURE_2D, 1, format, w, h);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// std::runtime_error naming `what` unless the bound framebuffer is complete.
inline void check_framebuffer(const char* what) {
  const GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (st != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error(std::string("OpenGL framebuffer incomplete (") + std::to_string(st) + ") in " + what);
}

// A w x h render target: float RGBA colour and 32-bit float depth (storage_2d), both
// attached to `fbo`, which is left bound and draws to the colour; std::runtime_error
// naming `what` unless it is complete.
inline void colour_depth_target(GLuint fbo, GLuint colour, GLuint depth, int w, int h, const char* what) {
  storage_2d(colour, GL_RGBA32F, w, h);
  storage_2d(depth, GL_DEPTH_COMPONENT32F, w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
  const GLenum draw = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &draw);
  check_framebuffer(what);
}

// The embedded shader source at `path` as a program's only part.
inline std::vector<ShaderPart> parts(const char* path) { return {embedded_source(path)}; }

}  // namespace atmosh::gpu::detail
