// Rasterisation of gi meshes: G-buffer with the sun's shadow map, reflective shadow map
// (see gi_raster.hpp).
#include "atmosh/gpu/gi_raster.hpp"
#include "atmosh/gpu/pixel_ray.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "atmosh/gpu/program.hpp"
#include "gl_objects.hpp"

namespace atmosh::gpu {

namespace {
using Clock = std::chrono::steady_clock;

using namespace detail;  // gl_objects.hpp

// The mesh as a triangle soup in float relative to the bounding-box centre: position,
// normal, albedo, emission + one-sided flag (13 floats a vertex).
struct Soup {
  glm::dvec3 centre{0.0};
  double radius = 1;
  VertexArrays vao{1};
  GlBuffers vbo{1};
  GLsizei count = 0;
};

void upload(const GiMeshView& m, Soup& s) {
  if (!m.positions || !m.triangles || !m.normal || !m.albedo || !m.emission || m.positions->empty() ||
      m.triangles->empty())
    throw std::invalid_argument("gi raster: positions, triangles, normals, albedo and emission are required");
  const std::size_t nt = m.triangles->size();
  if (m.normal->size() != nt || m.albedo->size() != nt || m.emission->size() != nt ||
      (m.one_sided && m.one_sided->size() != nt))
    throw std::invalid_argument("gi raster: per-triangle attributes must have one entry a triangle");
  const auto& P = *m.positions;
  glm::dvec3 lo = P[0], hi = P[0];
  for (const auto& p : P) lo = glm::min(lo, p), hi = glm::max(hi, p);
  s.centre = 0.5 * (lo + hi);
  s.radius = std::max(0.5 * glm::length(hi - lo), 1e-30) * 1.01;
  std::vector<float> v;
  v.reserve(nt * 3 * 13);
  for (std::size_t t = 0; t < nt; ++t) {
    const glm::dvec3 n = (*m.normal)[t], a = (*m.albedo)[t], e = (*m.emission)[t];
    const double one = m.one_sided && (*m.one_sided)[t] ? 1.0 : 0.0;
    for (std::uint32_t i : (*m.triangles)[t]) {
      if (i >= P.size()) throw std::invalid_argument("gi raster: triangle index out of range");
      const glm::dvec3 p = P[i] - s.centre;
      for (double x : {p.x, p.y, p.z, n.x, n.y, n.z, a.x, a.y, a.z, e.x, e.y, e.z, one})
        v.push_back(static_cast<float>(x));
    }
  }
  s.count = static_cast<GLsizei>(nt * 3);
  glBindVertexArray(s.vao.ids[0]);
  glBindBuffer(GL_ARRAY_BUFFER, s.vbo.ids[0]);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(v.size() * sizeof(float)), v.data(), GL_STATIC_DRAW);
  const GLsizei stride = 13 * sizeof(float);
  const int sizes[4] = {3, 3, 3, 4};
  std::size_t off = 0;
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(off * sizeof(float)));
    off += static_cast<std::size_t>(sizes[a]);
  }
  check_gl("gi raster: mesh upload");
}


// Reads attachment `att` of the bound read framebuffer (RGBA float, GL rows from the bottom).
std::vector<float> read_rgba(GLuint fb, int att, int w, int h) {
  std::vector<float> out(static_cast<std::size_t>(w) * h * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(att));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, out.data());
  check_gl("gi raster: read-back");
  return out;
}

// A framebuffer of `n` RGBA32F colour targets and a 32F depth buffer, cleared.
void colour_targets(GLuint fb, const Textures& tex, int n, int w, int h, const char* what) {
  for (int i = 0; i <= n; ++i)
    storage_2d(tex.ids[static_cast<std::size_t>(i)], i < n ? GL_RGBA32F : GL_DEPTH_COMPONENT32F, w, h);
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  std::vector<GLenum> draw;
  for (int i = 0; i < n; ++i) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D,
                           tex.ids[static_cast<std::size_t>(i)], 0);
    draw.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  }
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex.ids[static_cast<std::size_t>(n)], 0);
  glDrawBuffers(n, draw.data());
  check_framebuffer(what);
  glViewport(0, 0, w, h);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < n; ++i) glClearBufferfv(GL_COLOR, i, zero);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
}

glm::dvec3 rgb(const std::vector<float>& v, std::size_t p) { return {v[4 * p], v[4 * p + 1], v[4 * p + 2]}; }
}  // namespace

namespace {
void check_gbuffer_inputs(const PrtCamera& cam, const GiSun* sun, const GiShadowOptions& so, const GiEmitterOptions* eo,
                          const GiSkyOptions* sky) {
  if (cam.width < 1 || cam.height < 1 || cam.width > 16384 || cam.height > 16384 || !(cam.tan_half_fov > 0) ||
      !std::isfinite(cam.tan_half_fov))
    throw std::invalid_argument("gi_gbuffer: bad camera");
  if (so.resolution < 16 || so.resolution > 16384 || so.pcf < 0 || so.pcf > 4 || !(so.normal_offset >= 0) ||
      !(so.bias >= 0) || !std::isfinite(so.normal_offset + so.bias))
    throw std::invalid_argument("gi_gbuffer: shadow-map options out of range");
  if (sun && !(glm::length(sun->direction) > 0 && std::isfinite(glm::length(sun->direction))))
    throw std::invalid_argument("gi_gbuffer: the sun's direction must be finite and non-zero");
  if (eo && (eo->points_per_triangle < 1 || eo->points_per_triangle > 64 || eo->resolution < 16 ||
             eo->resolution > 4096 || !(eo->eval_offset >= 0) || !(eo->shadow_offset >= 0) ||
             !std::isfinite(eo->eval_offset + eo->shadow_offset)))
    throw std::invalid_argument("gi_gbuffer: emitter options out of range");
  if (sky && (sky->directions.size() != sky->radiance.size() || sky->directions.size() > 1024 ||
              sky->resolution < 16 || sky->resolution > 8192))
    throw std::invalid_argument("gi_gbuffer: sky options out of range");
}

// The programs of the G-buffer pass (compiled once per user: gi_gbuffer, GiLpvFrame).
struct GBufferPrograms {
  Program depth{parts("gpu/shaders/prt_depth.vert"), parts("gpu/shaders/prt_depth.frag")};
  Program gbuf{parts("gpu/shaders/gi_gbuffer.vert"),
               {embedded_source("apps/gi/include/atmosh/gi/shared/polygon.glsl.hpp"),
                embedded_source("gpu/shaders/gi_pixel_point.glsl"), embedded_source("gpu/shaders/gi_gbuffer.frag")}};
  std::unique_ptr<Program> dist;  // the emitters' distance maps, made when first needed
};

// The G-buffer's targets (fresh per frame: immutable texture storage).
struct GBufferTargets {
  Textures tex{7};  // 6 colour targets + depth
  Framebuffers fbo{1};
};

// The lights' maps — the sun's shadow map, the emitters' distance maps, the sky's depth maps —
// with their buffers. They depend on the mesh and the lights alone, not on the camera: a caller
// that draws many frames of one mesh (GiLpvFrame) keeps each part while its `key` (the inputs it
// was made from) is unchanged, so that a moving sun re-renders its shadow map alone and a changed
// sky radiance none; gi_gbuffer makes them once per call. The sky's direction buffer (with the
// radiance) is rebuilt every frame.
struct ShadowPart {
  Textures tex{1};
  Framebuffers fbo{1};
  std::vector<double> key;
};
struct EmitterPart {
  Textures tex{2};  // the distance maps, their depth buffer
  Framebuffers fbo{1};
  std::unique_ptr<Buffer> b_tri, b_pts;
  std::vector<double> key;
  int n_em = 0, K = 1, C = 1;
};
struct SkyPart {
  Textures tex{1};
  Framebuffers fbo{1};
  std::vector<double> key;
  int n_sky = 0, S = 1;
};
struct LightMaps {
  std::unique_ptr<ShadowPart> shadow;
  std::unique_ptr<EmitterPart> emitters;
  std::unique_ptr<SkyPart> sky;
  std::unique_ptr<Buffer> b_sky;
};

std::vector<double> shadow_key(const GiSun* sun, const GiShadowOptions& so) {
  if (!sun) return {0.0};
  return {1.0, sun->direction.x, sun->direction.y, sun->direction.z, static_cast<double>(so.resolution)};
}
std::vector<double> emitter_key(const GiEmitterOptions* eo) {
  if (!eo) return {0.0};
  return {1.0, static_cast<double>(eo->points_per_triangle), static_cast<double>(eo->resolution)};
}
std::vector<double> sky_key(const GiSkyOptions* sky) {
  if (!sky) return {-1.0};
  std::vector<double> k{static_cast<double>(sky->directions.size()), static_cast<double>(sky->resolution)};
  for (const glm::dvec3& w : sky->directions) k.insert(k.end(), {w.x, w.y, w.z});
  return k;
}

// The frame of sky direction w's orthographic depth map: ex, ey.
void sky_axes(const glm::dvec3& w, glm::dvec3& ex, glm::dvec3& ey) {
  ex = glm::normalize(std::abs(w.z) < 0.9 ? glm::cross(glm::dvec3(0, 0, 1), w) : glm::cross(glm::dvec3(1, 0, 0), w));
  ey = glm::cross(w, ex);
}

// The projection of a cube face (forward f, right r, up u) seen from y: clip = (x . r, x . u,
// za (x . f) + zb, x . f), x = p - y; the emitters' distance maps and RSMs.
Mat4 cube_face_matrix(const glm::dvec3& f, const glm::dvec3& r, const glm::dvec3& u, const glm::dvec3& y, double za,
                      double zb) {
  Mat4 m;
  for (int c = 0; c < 3; ++c) {
    m.set(0, c, r[c]);
    m.set(1, c, u[c]);
    m.set(2, c, za * f[c]);
    m.set(3, c, f[c]);
  }
  m.set(0, 3, -glm::dot(r, y));
  m.set(1, 3, -glm::dot(u, y));
  m.set(2, 3, -za * glm::dot(f, y) + zb);
  m.set(3, 3, -glm::dot(f, y));
  return m;
}

// Point k of the K fixed points of triangle (a, b, c) where the emitters' distance maps and
// RSMs are made: the Hammersley point ((k + 1/2) / K, radical inverse of k), sqrt-mapped onto
// the triangle.
glm::dvec3 emitter_point(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int k, int K) {
  double u2 = 0, base = 0.5;
  for (unsigned q = static_cast<unsigned>(k); q; q >>= 1, base *= 0.5) u2 += (q & 1u) * base;
  const double r = std::sqrt((k + 0.5) / K);
  return (1 - r) * a + r * (1 - u2) * b + r * u2 * c;
}

// The emitting triangles of a mesh (emission summed over the channels > 0), at most 64.
std::vector<std::size_t> emitting_triangles(const GiMeshView& mesh, const char* who) {
  std::vector<std::size_t> out;
  for (std::size_t t = 0; t < mesh.triangles->size(); ++t) {
    const glm::dvec3 L = (*mesh.emission)[t];
    if (!(L.x + L.y + L.z > 0)) continue;
    if (out.size() == 64) throw std::invalid_argument(std::string(who) + ": more than 64 emitting triangles");
    out.push_back(t);
  }
  return out;
}

// The cube-map face frames of the emitters' distance maps: forward, right, up (the same in the
// rendering and the shader's lookup).
void face_frames(glm::dvec3 (&ff)[6], glm::dvec3 (&fr)[6], glm::dvec3 (&fu)[6]) {
  for (int f = 0; f < 6; ++f) {
    glm::dvec3 F(0.0);
    F[f / 2] = f % 2 == 0 ? 1.0 : -1.0;
    const glm::dvec3 helper = f / 2 == 1 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    ff[f] = F;
    fr[f] = glm::normalize(glm::cross(F, helper));
    fu[f] = glm::cross(fr[f], F);
  }
}

// 1. The sun's depth map (a 1 x 1 cleared map without a sun).
void draw_shadow_map(const Soup& soup, const Program& depth, ShadowPart& M, const GiSun* sun, const GiShadowOptions& so) {
  const double radius = soup.radius;
  const int D = so.resolution;
  const GLuint t_shadow = M.tex.ids[0];
  const glm::dvec3 s = sun ? glm::normalize(sun->direction) : glm::dvec3(0, 0, 1);
  const Mat4 lp = light_matrix(s, radius);
  storage_2d(t_shadow, GL_DEPTH_COMPONENT32F, sun ? D : 1, sun ? D : 1);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, M.fbo.ids[0]);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t_shadow, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  check_framebuffer("gi shadow map");
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  if (sun) {  // 1. the sun's depth map
    glViewport(0, 0, D, D);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    depth.use();
    depth.set_mat4("light_proj", lp.m);
    glBindVertexArray(soup.vao.ids[0]);
    glDrawArrays(GL_TRIANGLES, 0, soup.count);
    check_gl("gi shadow map pass");
  }
}

// 2. Area emitters: sample points and their distance cube maps.
void draw_emitter_maps(const GiMeshView& mesh, const Soup& soup, GBufferPrograms& P, EmitterPart& M,
                       const GiEmitterOptions* eo) {
  const double radius = soup.radius;
  const GLuint t_emaps = M.tex.ids[0], t_edepth = M.tex.ids[1];
  std::vector<float> etri, epts;
  int n_em = 0, K = 1, C = 1;
  glm::dvec3 ff[6], fr[6], fu[6];
  face_frames(ff, fr, fu);
  if (eo) {
    K = eo->points_per_triangle;
    C = eo->resolution;
    const auto& P = *mesh.positions;
    for (std::size_t t = 0; t < mesh.triangles->size(); ++t) {
      const glm::dvec3 L = (*mesh.emission)[t];
      if (!(L.x + L.y + L.z > 0)) continue;
      if (++n_em > 64) throw std::invalid_argument("gi_gbuffer: more than 64 emitting triangles");
      const auto& tv = (*mesh.triangles)[t];
      const glm::dvec3 a = P[tv[0]] - soup.centre, b = P[tv[1]] - soup.centre, c = P[tv[2]] - soup.centre;
      const glm::dvec3 n = (*mesh.normal)[t];
      const double one = mesh.one_sided && (*mesh.one_sided)[t] ? 1.0 : 0.0;
      for (const glm::dvec3& v : {a, b, c, L, n})
        for (int i = 0; i < 3; ++i) etri.push_back(static_cast<float>(v[i]));
      etri.push_back(static_cast<float>(one));
      for (int k = 0; k < K; ++k) {
        const glm::dvec3 y = emitter_point(a, b, c, k, K);
        for (int i = 0; i < 3; ++i) epts.push_back(static_cast<float>(y[i]));
        epts.push_back(static_cast<float>(n_em - 1));
      }
    }
  }
  const int layers = std::max(6, 6 * n_em * K);
  glBindTexture(GL_TEXTURE_2D_ARRAY, t_emaps);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_R32F, n_em ? C : 1, n_em ? C : 1, layers);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  check_gl("gi emitter maps");
  if (n_em > 0) {
    if (!P.dist)
      P.dist = std::make_unique<Program>(parts("gpu/shaders/gi_gbuffer.vert"), parts("gpu/shaders/gi_distance.frag"));
    const Program& dist = *P.dist;
    storage_2d(t_edepth, GL_DEPTH_COMPONENT32F, C, C);
    glBindFramebuffer(GL_FRAMEBUFFER, M.fbo.ids[0]);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t_edepth, 0);
    const GLenum d0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &d0);
    glViewport(0, 0, C, C);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    dist.use();
    glBindVertexArray(soup.vao.ids[0]);
    const double near_d = 1e-4 * radius, far_d = 4 * radius;
    const double za = (far_d + near_d) / (far_d - near_d), zb = -2.0 * far_d * near_d / (far_d - near_d);
    const float far_value[4] = {3.0e38f, 0, 0, 0};
    for (int k = 0; k < n_em * K; ++k) {
      const glm::dvec3 y(epts[4 * k], epts[4 * k + 1], epts[4 * k + 2]);
      dist.set("origin", static_cast<float>(y.x), static_cast<float>(y.y), static_cast<float>(y.z));
      for (int f = 0; f < 6; ++f) {
        glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, t_emaps, 0, 6 * k + f);
        if (k == 0 && f == 0) check_framebuffer("gi emitter distance maps");
        glClearBufferfv(GL_COLOR, 0, far_value);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        dist.set_mat4("view_proj", cube_face_matrix(ff[f], fr[f], fu[f], y, za, zb).m);
        glDrawArrays(GL_TRIANGLES, 0, soup.count);
      }
    }
    check_gl("gi emitter distance maps");
  }
  if (etri.empty()) etri.assign(16, 0.0f);
  if (epts.empty()) epts.assign(4, 0.0f);
  M.b_tri = std::make_unique<Buffer>(etri.size() * sizeof(float), etri.data());
  M.b_pts = std::make_unique<Buffer>(epts.size() * sizeof(float), epts.data());
  M.n_em = n_em, M.K = K, M.C = C;
}

// 3. Sky directions: an orthographic depth map each (layers of a depth array).
void draw_sky_maps(const Soup& soup, const Program& depth, SkyPart& M, const GiSkyOptions* sky) {
  const double radius = soup.radius;
  const GLuint t_sky = M.tex.ids[0];
  const int n_sky = sky ? static_cast<int>(sky->directions.size()) : 0, S = sky ? sky->resolution : 1;
  glBindTexture(GL_TEXTURE_2D_ARRAY, t_sky);
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, n_sky ? S : 1, n_sky ? S : 1, std::max(n_sky, 1));
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  check_gl("gi sky maps");
  if (n_sky > 0) {
    glBindFramebuffer(GL_FRAMEBUFFER, M.fbo.ids[0]);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    glViewport(0, 0, S, S);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    depth.use();
    glBindVertexArray(soup.vao.ids[0]);
    for (int k = 0; k < n_sky; ++k) {
      const glm::dvec3 w = sky->directions[static_cast<std::size_t>(k)];
      if (!(std::abs(glm::length(w) - 1) < 1e-6)) throw std::invalid_argument("gi_gbuffer: sky directions must be unit");
      glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, t_sky, 0, k);
      if (k == 0) check_framebuffer("gi sky maps");
      glClearDepth(1.0);
      glClear(GL_DEPTH_BUFFER_BIT);
      const Mat4 lk = light_matrix(w, radius);
      depth.set_mat4("light_proj", lk.m);
      glDrawArrays(GL_TRIANGLES, 0, soup.count);
    }
    check_gl("gi sky maps");
  }
  M.n_sky = n_sky, M.S = S;
}

// The lights' maps of `M` that its parts do not hold for these lights, made afresh (the context
// current, `soup` uploaded): 1. the sun's shadow map, 2. the emitters' sample points and distance
// cube maps, 3. the sky directions' depth maps; and the sky's direction buffer.
void update_light_maps(const GiMeshView& mesh, const Soup& soup, GBufferPrograms& P, LightMaps& M, const GiSun* sun,
                       const GiShadowOptions& so, const GiEmitterOptions* eo, const GiSkyOptions* sky) {
  const Program& depth = P.depth;
  if (!M.shadow || M.shadow->key != shadow_key(sun, so)) {
    M.shadow = std::make_unique<ShadowPart>();
    draw_shadow_map(soup, depth, *M.shadow, sun, so);
    M.shadow->key = shadow_key(sun, so);  // after a complete drawing (a throw leaves the part to be redrawn)
  }
  if (!M.emitters || M.emitters->key != emitter_key(eo)) {
    M.emitters = std::make_unique<EmitterPart>();
    draw_emitter_maps(mesh, soup, P, *M.emitters, eo);
    M.emitters->key = emitter_key(eo);  // after a complete drawing (a throw leaves the part to be redrawn)
  }
  if (!M.sky || M.sky->key != sky_key(sky)) {
    M.sky = std::make_unique<SkyPart>();
    draw_sky_maps(soup, depth, *M.sky, sky);
    M.sky->key = sky_key(sky);  // after a complete drawing (a throw leaves the part to be redrawn)
  }
  // The sky directions' buffer: 12 floats each (w, ex, ey, L x weight).
  std::vector<float> skyd;
  for (std::size_t k = 0; sky && k < sky->directions.size(); ++k) {
    glm::dvec3 ex, ey;
    sky_axes(sky->directions[k], ex, ey);
    for (const glm::dvec3& v : {sky->directions[k], ex, ey, sky->radiance[k]})
      for (int i = 0; i < 3; ++i) skyd.push_back(static_cast<float>(v[i]));
  }
  if (skyd.empty()) skyd.assign(12, 0.0f);
  M.b_sky = std::make_unique<Buffer>(skyd.size() * sizeof(float), skyd.data());
}

// The area emitters' RSMs (gi_emitter_rsm): one atlas of 3 RGBA32F targets (position w = 1
// where a surface is, normal, flux; relative to the bounding-box centre) and its depth, the
// cube faces in square tiles of N x N texels, tile 6 k + f at column (6 k + f) mod cols.
struct EmitterRsmPart {
  Textures tex{4};
  Framebuffers fbo{1};
  std::vector<double> key;
  int width = 1, height = 1;
};

void check_emitter_rsm_options(const GiEmitterRsmOptions& o) {
  if (o.points_per_triangle < 1 || o.points_per_triangle > 64 || o.resolution < 2 || o.resolution > 1024)
    throw std::invalid_argument("gi_emitter_rsm: points per triangle must be 1..64 and the resolution 2..1024");
}

void draw_emitter_rsm(const GiMeshView& mesh, const Soup& soup, const Program& prog, EmitterRsmPart& M,
                      const GiEmitterRsmOptions& o) {
  check_emitter_rsm_options(o);
  const std::vector<std::size_t> tris = emitting_triangles(mesh, "gi_emitter_rsm");
  const int K = o.points_per_triangle, N = o.resolution;
  const int tiles = 6 * K * static_cast<int>(tris.size());
  const int cols = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(tiles)))));
  const int rows = std::max(1, (tiles + cols - 1) / cols);
  M.width = tiles ? cols * N : 1;
  M.height = tiles ? rows * N : 1;
  if (M.width > 16384 || M.height > 16384)
    throw std::invalid_argument("gi_emitter_rsm: the atlas would exceed 16384 texels a side");
  colour_targets(M.fbo.ids[0], M.tex, 3, M.width, M.height, "gi emitter RSM");
  if (tiles == 0) return;
  glm::dvec3 ff[6], fr[6], fu[6];
  face_frames(ff, fr, fu);
  const double radius = soup.radius;
  const double near_d = 1e-4 * radius, far_d = 4 * radius;
  const double za = (far_d + near_d) / (far_d - near_d), zb = -2.0 * far_d * near_d / (far_d - near_d);
  const auto& P = *mesh.positions;
  prog.use();
  prog.set("face_size", static_cast<float>(N));
  glBindVertexArray(soup.vao.ids[0]);
  int tile = 0;
  for (const std::size_t t : tris) {
    const auto& tv = (*mesh.triangles)[t];
    const glm::dvec3 a = P[tv[0]] - soup.centre, b = P[tv[1]] - soup.centre, c = P[tv[2]] - soup.centre;
    const glm::dvec3 ne = glm::normalize((*mesh.normal)[t]);
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    const glm::dvec3 power = (*mesh.emission)[t] * (area / K);
    prog.set("emitter_normal", static_cast<float>(ne.x), static_cast<float>(ne.y), static_cast<float>(ne.z));
    prog.set("one_sided", mesh.one_sided && (*mesh.one_sided)[t] ? 1 : 0);
    prog.set("point_power", static_cast<float>(power.x), static_cast<float>(power.y), static_cast<float>(power.z));
    for (int k = 0; k < K; ++k) {
      const glm::dvec3 y = emitter_point(a, b, c, k, K);
      prog.set("origin", static_cast<float>(y.x), static_cast<float>(y.y), static_cast<float>(y.z));
      for (int f = 0; f < 6; ++f, ++tile) {
        const int ox = (tile % cols) * N, oy = (tile / cols) * N;
        glViewport(ox, oy, N, N);
        prog.set_mat4("view_proj", cube_face_matrix(ff[f], fr[f], fu[f], y, za, zb).m);
        prog.set("tile_origin", static_cast<float>(ox), static_cast<float>(oy), 0.0f);
        for (const auto& [name, v] : {std::pair{"face_f", ff[f]}, std::pair{"face_r", fr[f]}, std::pair{"face_u", fu[f]}})
          prog.set(name, static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
        // the texel ray through window (x, y): f + u r + v up, u = 2 (x - ox) / N - 1 (pixel_ray.hpp's form)
        const double e = 2.0 / N;
        const glm::dvec3 d0 = ff[f] - fr[f] - fu[f] - (ox * e) * fr[f] - (oy * e) * fu[f];
        const glm::dvec3 rays[3] = {d0, e * fr[f], e * fu[f]};
        const char* names[3] = {"pixel_ray[0]", "pixel_ray[1]", "pixel_ray[2]"};
        for (int q = 0; q < 3; ++q)
          prog.set(names[q], static_cast<float>(rays[q].x), static_cast<float>(rays[q].y), static_cast<float>(rays[q].z));
        glDrawArrays(GL_TRIANGLES, 0, soup.count);
      }
    }
  }
  check_gl("gi emitter RSM pass");
}

std::unique_ptr<Program> emitter_rsm_program() {
  return std::make_unique<Program>(
      parts("gpu/shaders/gi_gbuffer.vert"),
      std::vector<ShaderPart>{embedded_source("gpu/shaders/gi_pixel_point.glsl"),
                              embedded_source("gpu/shaders/gi_emitter_rsm.frag")});
}

// The G-buffer (6 RGBA32F targets in T.tex[0..5], framebuffer T.fbo[0]) of `cam`, with the
// lights' maps of `maps` (made or brought up to date first: update_light_maps); the context
// current, `soup` uploaded.
void draw_gbuffer(const GiMeshView& mesh, const Soup& soup, GBufferPrograms& P, GBufferTargets& T,
                  std::unique_ptr<LightMaps>& maps, const PrtCamera& cam, const GiSun* sun, const GiShadowOptions& so,
                  const GiEmitterOptions* eo, const GiSkyOptions* sky) {
  if (!maps) maps = std::make_unique<LightMaps>();
  update_light_maps(mesh, soup, P, *maps, sun, so, eo, sky);
  const LightMaps& M = *maps;
  const double radius = soup.radius;
  const int W = cam.width, H = cam.height, D = so.resolution;
  const Program& gbuf = P.gbuf;
  const GLuint t_shadow = M.shadow->tex.ids[0], t_emaps = M.emitters->tex.ids[0], t_sky = M.sky->tex.ids[0];
  const int n_em = M.emitters->n_em, K = M.emitters->K, C = M.emitters->C, n_sky = M.sky->n_sky, S = M.sky->S;
  const glm::dvec3 s = sun ? glm::normalize(sun->direction) : glm::dvec3(0, 0, 1);
  const Mat4 lp = light_matrix(s, radius);
  glm::dvec3 ff[6], fr[6], fu[6];
  face_frames(ff, fr, fu);
  M.emitters->b_tri->bind(0);
  M.emitters->b_pts->bind(1);
  M.b_sky->bind(2);

  // 4. G-buffer from the camera (prt.cpp's projection; near plane at least 1e-3 radius).
  colour_targets(T.fbo.ids[0], T.tex, 6, W, H, "gi G-buffer");
  const glm::dvec3 eye = cam.eye - soup.centre;
  const double dist = glm::length(eye);
  const double near_d = std::max(dist - radius, 1e-3 * radius), far_d = dist + radius;
  const Mat4 vp = camera_matrix(cam.right, cam.up, cam.back, cam.tan_half_fov, eye, W, H, near_d, far_d);
  gbuf.use();
  gbuf.set_mat4("view_proj", vp.m);
  gbuf.set_mat4("light_proj", lp.m);
  gbuf.set("eye", static_cast<float>(eye.x), static_cast<float>(eye.y), static_cast<float>(eye.z));
  set_pixel_ray(gbuf, cam.right, cam.up, cam.back, cam.tan_half_fov, W, H);
  gbuf.set("has_sun", sun ? 1 : 0);
  gbuf.set("sun_dir", static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z));
  gbuf.set("shadow_res", sun ? D : 1);
  gbuf.set("texel", static_cast<float>(2.0 * radius / D));
  gbuf.set("radius", static_cast<float>(radius));
  gbuf.set("normal_offset", static_cast<float>(so.normal_offset));
  gbuf.set("bias", static_cast<float>(so.bias));
  gbuf.set("pcf", so.pcf);
  gbuf.set("shadow_map", 0);
  gbuf.set("n_emitters", n_em);
  gbuf.set("points_per_tri", K);
  gbuf.set("emitter_maps", 1);
  gbuf.set("emitter_res", C);
  gbuf.set("eval_offset", static_cast<float>(eo ? eo->eval_offset : 0.0));
  gbuf.set("shadow_offset", static_cast<float>(eo ? eo->shadow_offset : 0.0));
  for (int f = 0; f < 6; ++f) {
    std::string i = "[";  // appended: GCC 12 warns falsely (-Wrestrict, bug 105329) on "[" + std::string
    i += std::to_string(f);
    i += ']';
    gbuf.set(("face_f" + i).c_str(), static_cast<float>(ff[f].x), static_cast<float>(ff[f].y), static_cast<float>(ff[f].z));
    gbuf.set(("face_r" + i).c_str(), static_cast<float>(fr[f].x), static_cast<float>(fr[f].y), static_cast<float>(fr[f].z));
    gbuf.set(("face_u" + i).c_str(), static_cast<float>(fu[f].x), static_cast<float>(fu[f].y), static_cast<float>(fu[f].z));
  }
  gbuf.set("n_sky", n_sky);
  gbuf.set("sky_res", S);
  gbuf.set("sky_maps", 2);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D_ARRAY, t_sky);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D_ARRAY, t_emaps);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, t_shadow);
  glBindVertexArray(soup.vao.ids[0]);
  glDrawArrays(GL_TRIANGLES, 0, soup.count);
  check_gl("gi G-buffer pass");
}
}  // namespace

GiGBufferResult gi_gbuffer(const Context& ctx, const GiMeshView& mesh, const PrtCamera& cam, const GiSun* sun,
                           const GiShadowOptions& so, const GiEmitterOptions* eo, const GiSkyOptions* sky) {
  check_gbuffer_inputs(cam, sun, so, eo, sky);
  ctx.make_current();
  const auto t0 = Clock::now();
  Soup soup;
  upload(mesh, soup);
  const int W = cam.width, H = cam.height;
  GBufferPrograms P;
  GBufferTargets T;
  std::unique_ptr<LightMaps> maps;
  draw_gbuffer(mesh, soup, P, T, maps, cam, sun, so, eo, sky);
  Framebuffers& fbo = T.fbo;
  const std::vector<float> pos = read_rgba(fbo.ids[0], 0, W, H), nrm = read_rgba(fbo.ids[0], 1, W, H),
                           alb = read_rgba(fbo.ids[0], 2, W, H), emi = read_rgba(fbo.ids[0], 3, W, H),
                           eir = read_rgba(fbo.ids[0], 4, W, H), sir = read_rgba(fbo.ids[0], 5, W, H);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  GiGBufferResult r;
  r.width = W;
  r.height = H;
  const std::size_t np = static_cast<std::size_t>(W) * H;
  r.hit.assign(np, 0);
  for (auto* v : {&r.position, &r.normal, &r.albedo, &r.emission, &r.emitter, &r.sky}) v->assign(np, glm::dvec3(0.0));
  r.sun.assign(np, 0.0);
  for (std::size_t p = 0; p < np; ++p) {
    if (pos[4 * p + 3] == 0.0f) continue;
    const std::size_t row = static_cast<std::size_t>(H - 1) - p / static_cast<std::size_t>(W);
    const std::size_t q = row * static_cast<std::size_t>(W) + p % static_cast<std::size_t>(W);
    r.hit[q] = 1;
    r.position[q] = rgb(pos, p) + soup.centre;
    r.normal[q] = rgb(nrm, p);
    r.sun[q] = sun ? static_cast<double>(nrm[4 * p + 3]) : 0.0;
    r.albedo[q] = rgb(alb, p);
    r.emission[q] = rgb(emi, p);
    r.emitter[q] = rgb(eir, p);
    r.sky[q] = rgb(sir, p);
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

namespace {
// The reflective shadow map (3 RGBA32F targets in tex[0..2] of framebuffer fbo.ids[0]); the
// context current, `soup` uploaded.
void draw_rsm(const Soup& soup, const Program& prog, Textures& tex, Framebuffers& fbo, const GiRsmView& v) {
  const double radius = soup.radius;
  const glm::dvec3 s = glm::normalize(v.direction);
  // x_ndc = (2 (p.t) - (t0 + t1)) / (t1 - t0) with p = p_c + centre; likewise y on b; depth as
  // the shadow map's, (radius - p_c . s) / (2 radius).
  Mat4 lp;
  const double st = 2.0 / (v.t1 - v.t0), sb = 2.0 / (v.b1 - v.b0);
  for (int c = 0; c < 3; ++c) {
    lp.set(0, c, st * v.t[c]);
    lp.set(1, c, sb * v.b[c]);
    lp.set(2, c, -s[c] / radius);
  }
  lp.set(0, 3, st * glm::dot(soup.centre, v.t) - (v.t0 + v.t1) / (v.t1 - v.t0));
  lp.set(1, 3, sb * glm::dot(soup.centre, v.b) - (v.b0 + v.b1) / (v.b1 - v.b0));
  lp.set(3, 3, 1.0);
  colour_targets(fbo.ids[0], tex, 3, v.mt, v.mb, "gi RSM");
  const glm::dvec3 beam = v.irradiance * ((v.t1 - v.t0) * (v.b1 - v.b0) / (static_cast<double>(v.mt) * v.mb));
  prog.use();
  prog.set_mat4("view_proj", lp.m);
  prog.set("sun_dir", static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z));
  prog.set("beam_flux", static_cast<float>(beam.x), static_cast<float>(beam.y), static_cast<float>(beam.z));
  glBindVertexArray(soup.vao.ids[0]);
  glDrawArrays(GL_TRIANGLES, 0, soup.count);
  check_gl("gi RSM pass");
}

void check_rsm_view(const GiRsmView& v) {
  if (v.mt < 1 || v.mb < 1 || v.mt > 16384 || v.mb > 16384)
    throw std::invalid_argument("gi_rsm: texels per side must be in 1..16384");
  if (!(v.t1 > v.t0) || !(v.b1 > v.b0) || !std::isfinite(v.t1 - v.t0 + v.b1 - v.b0))
    throw std::invalid_argument("gi_rsm: empty or non-finite rectangle");
}
}  // namespace

GiRsmResult gi_rsm(const Context& ctx, const GiMeshView& mesh, const GiRsmView& v) {
  check_rsm_view(v);
  ctx.make_current();
  const auto t0 = Clock::now();
  Soup soup;
  upload(mesh, soup);
  const Program prog(parts("gpu/shaders/gi_gbuffer.vert"), parts("gpu/shaders/gi_rsm.frag"));
  Textures tex(4);
  Framebuffers fbo(1);
  draw_rsm(soup, prog, tex, fbo, v);
  const std::vector<float> pos = read_rgba(fbo.ids[0], 0, v.mt, v.mb), nrm = read_rgba(fbo.ids[0], 1, v.mt, v.mb),
                           flx = read_rgba(fbo.ids[0], 2, v.mt, v.mb);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  GiRsmResult r;
  r.width = v.mt;
  r.height = v.mb;
  const std::size_t np = static_cast<std::size_t>(v.mt) * v.mb;
  r.hit.assign(np, 0);
  for (auto* x : {&r.position, &r.normal, &r.flux}) x->assign(np, glm::dvec3(0.0));
  for (std::size_t p = 0; p < np; ++p) {
    if (pos[4 * p + 3] == 0.0f) continue;
    r.hit[p] = 1;
    r.position[p] = rgb(pos, p) + soup.centre;
    r.normal[p] = rgb(nrm, p);
    r.flux[p] = rgb(flx, p);
  }
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

GiEmitterRsmResult gi_emitter_rsm(const Context& ctx, const GiMeshView& mesh, const GiEmitterRsmOptions& o) {
  check_emitter_rsm_options(o);
  ctx.make_current();
  const auto t0 = Clock::now();
  Soup soup;
  upload(mesh, soup);
  const std::unique_ptr<Program> prog = emitter_rsm_program();
  EmitterRsmPart M;
  draw_emitter_rsm(mesh, soup, *prog, M, o);
  const std::vector<float> pos = read_rgba(M.fbo.ids[0], 0, M.width, M.height),
                           nrm = read_rgba(M.fbo.ids[0], 1, M.width, M.height),
                           flx = read_rgba(M.fbo.ids[0], 2, M.width, M.height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  GiEmitterRsmResult r;
  const std::size_t np = static_cast<std::size_t>(M.width) * M.height;
  for (std::size_t p = 0; p < np; ++p) {
    if (pos[4 * p + 3] == 0.0f) continue;
    r.position.push_back(rgb(pos, p) + soup.centre);
    r.normal.push_back(rgb(nrm, p));
    r.flux.push_back(rgb(flx, p));
  }
  r.texels = static_cast<std::size_t>(6 * o.points_per_triangle) * emitting_triangles(mesh, "gi_emitter_rsm").size() *
             static_cast<std::size_t>(o.resolution) * static_cast<std::size_t>(o.resolution);
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace atmosh::gpu

// ---------------------------------------------------------------------------------------------
// The GPU-resident LPV frame (gi_raster.hpp, GiLpvFrame).
namespace atmosh::gpu {

namespace {
std::vector<ShaderPart> lpv_parts(const char* path) {
  return {embedded_source("gpu/shaders/gi_lpv_decl.glsl"),
          embedded_source("apps/gi/include/atmosh/gi/shared/radiosity.glsl.hpp"),
          embedded_source("apps/gi/include/atmosh/gi/shared/lpv.glsl.hpp"), embedded_source(path)};
}

// An atlas of 3 RGBA32F targets (w x h), cleared, with additive blending for points.
void atlas_targets(GLuint fb, const Textures& tex, int w, int h, const char* what) {
  glBindFramebuffer(GL_FRAMEBUFFER, fb);
  GLenum draw[3];
  for (int i = 0; i < 3; ++i) {
    storage_2d(tex.ids[static_cast<std::size_t>(i)], GL_RGBA32F, w, h);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D,
                           tex.ids[static_cast<std::size_t>(i)], 0);
    draw[i] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i);
  }
  glDrawBuffers(3, draw);
  check_framebuffer(what);
  glViewport(0, 0, w, h);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
}

void bind_textures(const GLuint* ids, int n) {
  for (int i = 0; i < n; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    glBindTexture(GL_TEXTURE_2D, ids[i]);
  }
  glActiveTexture(GL_TEXTURE0);
}

// One grid of the frame: its cells (ping-pong), the running sum, and the open-face table of its
// geometry volume (shared by a cascade's coarse inner and outer grids). box_mode: 0 every VPL,
// 1 those inside the cascade's fine box, 2 those outside it; shift: the further move along n.
struct LpvLevel {
  GiLpvGrid grid;
  std::size_t n_cells = 0;
  std::unique_ptr<Buffer> cells_a, cells_b, acc;
  std::shared_ptr<Buffer> vis;
  int box_mode = 0;
  double shift = 0;
};

bool bad_grid(const GiLpvGrid& g) {
  return g.nx < 1 || g.ny < 1 || g.nz < 1 || g.nx > 16383 || static_cast<long long>(g.ny + 1) * (g.nz + 1) > 16384 ||
         !(g.h > 0) || !std::isfinite(g.h) || !std::isfinite(g.lo.x + g.lo.y + g.lo.z);
}
}  // namespace

struct GiLpvFrame::Impl {
  const Context& ctx;
  GiMeshView mesh;
  GiLpvGrid grid;
  Soup soup;
  GBufferPrograms gbuffer;
  std::unique_ptr<LightMaps> maps;  // the lights' maps of the last frame, kept while the lights are unchanged
  std::unique_ptr<Program> ersm_prog;     // the emitters' RSM program (made when first needed)
  std::unique_ptr<EmitterRsmPart> ersm;   // the emitters' RSMs, kept while their options are unchanged
  Program rsm{parts("gpu/shaders/gi_gbuffer.vert"), parts("gpu/shaders/gi_rsm.frag")};
  Program points{lpv_parts("gpu/shaders/gi_lpv_points.vert"), parts("gpu/shaders/gi_lpv_points.frag")};
  Program pack{parts("gpu/shaders/gi_lpv_pack.comp")};
  Program propagate{lpv_parts("gpu/shaders/gi_lpv_propagate.comp")};
  Program open{lpv_parts("gpu/shaders/gi_lpv_open.comp")};
  Program apply{lpv_parts("gpu/shaders/gi_lpv_frame_apply.comp")};
  VertexArrays empty{1};
  std::size_t n_vpls = 0;
  std::unique_ptr<Buffer> vpls;
  std::vector<LpvLevel> levels;  // one level; or a cascade's outer, inner and fine grids
  bool cascade = false;
  glm::dvec3 fine_lo{0.0}, fine_hi{0.0};
  double vpl_shift = 0;  // an RSM texel's move along n (half the finest cell edge)
  Impl(const Context& c, const GiMeshView& m, const GiLpvGrid& g) : ctx(c), mesh(m), grid(g) {}
  ~Impl() {  // the members' GL names are deleted in this context (where it is still alive)
    try {
      ctx.make_current();
    } catch (const std::exception&) {
    }
  }
  void set_grid(const Program& p, const GiLpvGrid& g, const char* lo, const char* h, const char* nx, const char* ny,
                const char* nz) const {
    const glm::dvec3 l = g.lo - soup.centre;
    p.set(lo, static_cast<float>(l.x), static_cast<float>(l.y), static_cast<float>(l.z));
    p.set(h, static_cast<float>(g.h));
    p.set(nx, g.nx);
    p.set(ny, g.ny);
    p.set(nz, g.nz);
  }
  void set_vec(const Program& p, const char* name, const glm::dvec3& v) const {
    p.set(name, static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z));
  }
  // The geometry volume of grid g: the surfels as points into the corner atlas, packed, then the
  // open fraction of every face (static geometry: once).
  std::shared_ptr<Buffer> open_faces(const GiLpvGrid& g, const std::vector<GiLpvSurfel>& surfels) {
    const std::size_t n_corners = static_cast<std::size_t>(g.nx + 1) * (g.ny + 1) * (g.nz + 1);
    const std::size_t n_cells = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
    const Buffer corners(n_corners * 9 * sizeof(float)), scratch(sizeof(float) * 12);
    std::vector<float> items;
    std::vector<std::uint32_t> corner_index;
    for (const GiLpvSurfel& sf : surfels) {
      corner_index.push_back(sf.corner);
      for (int c = 0; c < 3; ++c) items.push_back(static_cast<float>(sf.normal[c]));
      items.push_back(static_cast<float>(sf.weight));
    }
    if (items.empty()) items.assign(4, 0.0f), corner_index.assign(1, 0);
    const Buffer bs(items.size() * sizeof(float), items.data()),
        bc(corner_index.size() * sizeof(std::uint32_t), corner_index.data());
    Textures tex(3);
    Framebuffers fbo(1);
    const int cw = g.nx + 1, ch = (g.ny + 1) * (g.nz + 1);
    atlas_targets(fbo.ids[0], tex, cw, ch, "gi LPV geometry atlas");
    points.use();
    points.set("mode", 2);
    points.set("lpv_nx", g.nx + 1);
    points.set("lpv_ny", g.ny + 1);
    points.set("lpv_nz", g.nz + 1);
    bs.bind(0);
    bc.bind(1);
    glBindVertexArray(empty.ids[0]);
    if (!surfels.empty()) glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(surfels.size()));
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    check_gl("gi LPV geometry injection");
    bind_textures(tex.ids.data(), 3);
    pack.use();
    pack.set("atlas0", 0);
    pack.set("atlas1", 1);
    pack.set("atlas2", 2);
    pack.set("nx", g.nx + 1);
    pack.set("ny", g.ny + 1);
    pack.set("nz", g.nz + 1);
    pack.set("stride", 9);
    pack.set("write_acc", 0);
    corners.bind(0);
    scratch.bind(3);
    pack.dispatch(static_cast<unsigned>((n_corners + 63) / 64));
    check_gl("gi LPV geometry pack");
    auto vis = std::make_shared<Buffer>(n_cells * 30 * sizeof(float));
    open.use();
    open.set("nx", g.nx);
    open.set("ny", g.ny);
    open.set("nz", g.nz);
    corners.bind(1);
    vis->bind(2);
    open.dispatch(static_cast<unsigned>((n_cells + 63) / 64));
    check_gl("gi LPV open faces");
    glFinish();  // the corner buffers end here
    return vis;
  }
  void add_level(const GiLpvGrid& g, std::shared_ptr<Buffer> vis, int box_mode, double shift) {
    LpvLevel L;
    L.grid = g;
    L.n_cells = static_cast<std::size_t>(g.nx) * g.ny * g.nz;
    const std::size_t cb = L.n_cells * 12 * sizeof(float);
    L.cells_a = std::make_unique<Buffer>(cb);
    L.cells_b = std::make_unique<Buffer>(cb);
    L.acc = std::make_unique<Buffer>(cb);
    L.vis = std::move(vis);
    L.box_mode = box_mode;
    L.shift = shift;
    levels.push_back(std::move(L));
  }
};

GiLpvFrame::GiLpvFrame(const Context& ctx, const GiMeshView& mesh, const GiLpvGrid& g,
                       const std::vector<GiLpvSurfel>& surfels, const std::vector<GiLpvVpl>& vpls,
                       const GiLpvCascade* cascade) {
  if (bad_grid(g)) throw std::invalid_argument("GiLpvFrame: bad grid (cells >= 1, (ny + 1)(nz + 1) <= 16384, h > 0)");
  if (cascade != nullptr && (bad_grid(cascade->fine) || !(cascade->fine_lo.x <= cascade->fine_hi.x &&
                                                          cascade->fine_lo.y <= cascade->fine_hi.y &&
                                                          cascade->fine_lo.z <= cascade->fine_hi.z)))
    throw std::invalid_argument("GiLpvFrame: bad cascade (its fine grid as a grid, its box not empty)");
  auto check_surfels = [](const GiLpvGrid& gr, const std::vector<GiLpvSurfel>& sv) {
    const std::size_t n_corners = static_cast<std::size_t>(gr.nx + 1) * (gr.ny + 1) * (gr.nz + 1);
    for (const GiLpvSurfel& s : sv)
      if (s.corner >= n_corners || !std::isfinite(s.weight + s.normal.x + s.normal.y + s.normal.z))
        throw std::invalid_argument("GiLpvFrame: a surfel outside the grid or not finite");
    if (sv.size() > 0x7fffffffu / 4) throw std::invalid_argument("GiLpvFrame: too many VPLs or surfels");
  };
  check_surfels(g, surfels);
  if (cascade != nullptr) check_surfels(cascade->fine, cascade->fine_surfels);
  if (vpls.size() > 0x7fffffffu / 9) throw std::invalid_argument("GiLpvFrame: too many VPLs or surfels");
  ctx.make_current();
  impl_ = std::make_unique<Impl>(ctx, mesh, g);
  Impl& I = *impl_;
  upload(mesh, I.soup);
  std::vector<float> items;
  for (const GiLpvVpl& v : vpls) {
    const glm::dvec3 p = v.p - I.soup.centre;
    for (const glm::dvec3& x : {p, v.n, v.flux})
      for (int c = 0; c < 3; ++c) items.push_back(static_cast<float>(x[c]));
  }
  I.n_vpls = vpls.size();
  if (items.empty()) items.assign(9, 0.0f);
  I.vpls = std::make_unique<Buffer>(items.size() * sizeof(float), items.data());
  std::shared_ptr<Buffer> vis = I.open_faces(g, surfels);
  if (cascade == nullptr) {
    I.vpl_shift = 0.5 * g.h;
    I.add_level(g, vis, 0, 0.0);
  } else {
    I.cascade = true;
    I.fine_lo = cascade->fine_lo;
    I.fine_hi = cascade->fine_hi;
    I.vpl_shift = 0.5 * cascade->fine.h;
    const double shift = 0.5 * g.h - I.vpl_shift;  // to the coarse level's half-cell shift
    I.add_level(g, vis, 2, shift);                 // outer
    I.add_level(g, vis, 1, shift);                 // inner
    I.add_level(cascade->fine, I.open_faces(cascade->fine, cascade->fine_surfels), 1, 0.0);
  }
  glBindVertexArray(0);
}

GiLpvFrame::~GiLpvFrame() = default;

GiLpvFrameResult GiLpvFrame::render(const PrtCamera& cam, const GiLpvFrameOptions& o) {
  Impl& I = *impl_;
  check_gbuffer_inputs(cam, o.sun, o.shadow, o.emitters, o.sky);
  if (o.iterations < 0 || o.iterations > 1024) throw std::invalid_argument("GiLpvFrame: iterations must be in 0..1024");
  if (o.rsm) check_rsm_view(*o.rsm);
  if (o.emitter_rsm) check_emitter_rsm_options(*o.emitter_rsm);
  if (!std::isfinite(o.sun_irradiance.x + o.sun_irradiance.y + o.sun_irradiance.z))
    throw std::invalid_argument("GiLpvFrame: the sun's irradiance must be finite");
  I.ctx.make_current();
  const auto t0 = Clock::now();
  // 1. G-buffer (with its shadow map and the lights' maps).
  GBufferTargets T;
  draw_gbuffer(I.mesh, I.soup, I.gbuffer, T, I.maps, cam, o.sun, o.shadow, o.emitters, o.sky);
  // 2. The sun's reflective shadow map.
  Textures rtex(4);
  Framebuffers rfbo(1);
  if (o.rsm) draw_rsm(I.soup, I.rsm, rtex, rfbo, *o.rsm);
  // 2b. The area emitters' RSMs (static: made once for these options).
  if (o.emitter_rsm) {
    const std::vector<double> key{static_cast<double>(o.emitter_rsm->points_per_triangle),
                                  static_cast<double>(o.emitter_rsm->resolution)};
    if (!I.ersm || I.ersm->key != key) {
      if (!I.ersm_prog) I.ersm_prog = emitter_rsm_program();
      I.ersm = std::make_unique<EmitterRsmPart>();
      draw_emitter_rsm(I.mesh, I.soup, *I.ersm_prog, *I.ersm, *o.emitter_rsm);
      I.ersm->key = key;
    }
  }
  for (LpvLevel& L : I.levels) {
    const GiLpvGrid& g = L.grid;
    // 3. Injection: RSM texels and the given VPLs as points into the level's cell atlas.
    Textures atex(3);
    Framebuffers afbo(1);
    atlas_targets(afbo.ids[0], atex, g.nx, g.ny * g.nz, "gi LPV injection atlas");
    I.points.use();
    I.set_grid(I.points, g, "lpv_lo", "lpv_h", "lpv_nx", "lpv_ny", "lpv_nz");
    I.points.set("vpl_shift", static_cast<float>(I.vpl_shift));
    I.points.set("box_mode", L.box_mode);
    I.set_vec(I.points, "box_lo", I.fine_lo - I.soup.centre);
    I.set_vec(I.points, "box_hi", I.fine_hi - I.soup.centre);
    I.points.set("level_shift", static_cast<float>(L.shift));
    glBindVertexArray(I.empty.ids[0]);
    if (o.rsm) {
      bind_textures(rtex.ids.data(), 3);
      I.points.set("mode", 0);
      I.points.set("rsm_position", 0);
      I.points.set("rsm_normal", 1);
      I.points.set("rsm_flux", 2);
      I.points.set("rsm_width", o.rsm->mt);
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(o.rsm->mt) * o.rsm->mb);
    }
    if (o.emitter_rsm) {  // the emitters' RSM texels, the same way
      bind_textures(I.ersm->tex.ids.data(), 3);
      I.points.set("mode", 0);
      I.points.set("rsm_position", 0);
      I.points.set("rsm_normal", 1);
      I.points.set("rsm_flux", 2);
      I.points.set("rsm_width", I.ersm->width);
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(I.ersm->width) * I.ersm->height);
    }
    if (I.n_vpls > 0) {
      I.points.set("mode", 1);
      I.vpls->bind(0);
      glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(I.n_vpls));
    }
    glDisable(GL_BLEND);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    check_gl("gi LPV injection");
    // 4. Pack into the cells' buffer and the running sum.
    bind_textures(atex.ids.data(), 3);
    I.pack.use();
    I.pack.set("atlas0", 0);
    I.pack.set("atlas1", 1);
    I.pack.set("atlas2", 2);
    I.pack.set("nx", g.nx);
    I.pack.set("ny", g.ny);
    I.pack.set("nz", g.nz);
    I.pack.set("stride", 12);
    I.pack.set("write_acc", 1);
    L.cells_a->bind(0);
    L.acc->bind(3);
    const unsigned groups = static_cast<unsigned>((L.n_cells + 63) / 64);
    I.pack.dispatch(groups);
    // 5. Propagation.
    I.propagate.use();
    I.propagate.set("nx", g.nx);
    I.propagate.set("ny", g.ny);
    I.propagate.set("nz", g.nz);
    I.propagate.set("lpv_reemission", o.reemission);
    L.vis->bind(1);
    L.acc->bind(3);
    for (int it = 0; it < o.iterations; ++it) {
      (it % 2 == 0 ? *L.cells_a : *L.cells_b).bind(0);
      (it % 2 == 0 ? *L.cells_b : *L.cells_a).bind(2);
      I.propagate.set("use_vis", o.blocking && it > 0 ? 1 : 0);
      I.propagate.dispatch(groups);
    }
    check_gl("gi LPV propagation");
  }
  // 6. Application to the G-buffer.
  const int W = cam.width, H = cam.height;
  const std::size_t np = static_cast<std::size_t>(W) * H;
  const Buffer out(np * 4 * sizeof(float));
  bind_textures(T.tex.ids.data(), 6);
  I.apply.use();
  const char* names[6] = {"g_position", "g_normal", "g_albedo", "g_emission", "g_emitter", "g_sky"};
  for (int i = 0; i < 6; ++i) I.apply.set(names[i], i);
  I.apply.set("width", W);
  I.apply.set("height", H);
  I.apply.set("sun_irradiance", static_cast<float>(o.sun ? o.sun_irradiance.x : 0.0),
              static_cast<float>(o.sun ? o.sun_irradiance.y : 0.0), static_cast<float>(o.sun ? o.sun_irradiance.z : 0.0));
  I.set_grid(I.apply, I.grid, "lpv_lo", "lpv_h", "lpv_nx", "lpv_ny", "lpv_nz");
  I.apply.set("cascade", I.cascade ? 1 : 0);
  const LpvLevel& fine = I.levels.back();
  I.set_grid(I.apply, fine.grid, "fine_grid_lo", "fine_h", "fine_nx", "fine_ny", "fine_nz");
  I.set_vec(I.apply, "fine_lo", I.fine_lo - I.soup.centre);
  I.set_vec(I.apply, "fine_hi", I.fine_hi - I.soup.centre);
  I.set_vec(I.apply, "lpv_hi", I.grid.lo + I.grid.h * glm::dvec3(I.grid.nx, I.grid.ny, I.grid.nz) - I.soup.centre);
  out.bind(5);
  I.levels[0].acc->bind(6);
  I.levels[I.cascade ? 1 : 0].acc->bind(7);
  fine.acc->bind(8);
  I.apply.dispatch(static_cast<unsigned>((W + 7) / 8), static_cast<unsigned>((H + 7) / 8));
  check_gl("gi LPV application");
  // 7. The image back.
  GiLpvFrameResult r;
  r.width = W;
  r.height = H;
  r.radiance.resize(np * 4);
  out.download(r.radiance.data(), r.radiance.size() * sizeof(float));
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (o.read_grid) {
    auto read = [](const LpvLevel& L, std::vector<float>& v) {
      v.resize(L.n_cells * 12);
      L.acc->download(v.data(), v.size() * sizeof(float));
    };
    read(I.levels[0], r.grid);
    if (I.cascade) {
      read(I.levels[1], r.inner);
      read(I.levels[2], r.fine);
    }
  }
  glBindVertexArray(0);
  return r;
}

}  // namespace atmosh::gpu
