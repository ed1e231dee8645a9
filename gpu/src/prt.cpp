// Per-pixel diffuse transfer by the depth-map method (see prt.hpp).
#include "atmosh/gpu/prt.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "atmosh/gpu/program.hpp"
#include "gl_objects.hpp"

namespace atmosh::gpu {

namespace {
using Clock = std::chrono::steady_clock;

using namespace detail;  // gl_objects.hpp
}  // namespace

PrtPixelResult prt_pixel_transfer(const Context& ctx, const PrtMeshView& mesh, const PrtCamera& cam,
                                  const sh::prt::SampleSet& samples, const PrtPixelOptions& opt) {
  if (!mesh.positions || !mesh.normals || !mesh.albedo || !mesh.triangles || mesh.positions->empty() ||
      mesh.normals->size() != mesh.positions->size() || mesh.albedo->size() != mesh.positions->size())
    throw std::invalid_argument("prt_pixel_transfer: positions, normals and albedo must be given per vertex");
  if (cam.width < 1 || cam.height < 1 || cam.width > 16384 || cam.height > 16384 || !(cam.tan_half_fov > 0))
    throw std::invalid_argument("prt_pixel_transfer: bad camera");
  if (opt.depth_resolution < 16 || opt.depth_resolution > 16384)
    throw std::invalid_argument("prt_pixel_transfer: depth_resolution must be in 16..16384, got " +
                                std::to_string(opt.depth_resolution));
  const int K = samples.coeffs();
  if (K < 1 || samples.dirs.empty()) throw std::invalid_argument("prt_pixel_transfer: empty sample set");
  ctx.make_current();
  const auto t0 = Clock::now();
  const auto& P = *mesh.positions;
  const auto& N = *mesh.normals;
  const auto& A = *mesh.albedo;
  const auto& T = *mesh.triangles;

  // Frame centred on the bounding box (float positions keep their precision).
  glm::dvec3 lo = P[0], hi = P[0];
  for (const auto& p : P) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * glm::length(hi - lo), 1e-30) * 1.01;

  std::vector<float> vertices;
  vertices.reserve(P.size() * 7);
  for (std::size_t v = 0; v < P.size(); ++v) {
    const glm::dvec3 p = P[v] - centre;
    for (double x : {p.x, p.y, p.z, N[v].x, N[v].y, N[v].z, A[v]}) vertices.push_back(static_cast<float>(x));
  }
  std::vector<GLuint> indices;
  indices.reserve(T.size() * 3);
  for (const auto& t : T)
    for (auto i : t) {
      if (i >= P.size()) throw std::invalid_argument("prt_pixel_transfer: triangle index out of range");
      indices.push_back(i);
    }

  const int W = cam.width, H = cam.height, D = opt.depth_resolution;
  GLint max_draw = 1, max_attach = 1;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_draw);
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &max_attach);
  const int channels = K + 1;  // coefficients, then the cosine sum (AO)
  const int targets = std::max(1, std::min({static_cast<int>(max_draw), static_cast<int>(max_attach), 8,
                                            (channels + 3) / 4}));
  const int passes = (channels + 4 * targets - 1) / (4 * targets);

  static const std::string kTargetsDefine = "#define TARGETS ";
  const Program gbuffer(parts("gpu/shaders/prt_gbuffer.vert"), parts("gpu/shaders/prt_gbuffer.frag"));
  const Program depth(parts("gpu/shaders/prt_depth.vert"), parts("gpu/shaders/prt_depth.frag"));
  const Program accumulate(parts("gpu/shaders/prt_accumulate.vert"), parts("gpu/shaders/prt_accumulate.frag"),
                           kTargetsDefine + std::to_string(targets) + "\n");

  // Geometry.
  VertexArrays vao(2);
  GlBuffers buf(2);
  glBindVertexArray(vao.ids[0]);
  glBindBuffer(GL_ARRAY_BUFFER, buf.ids[0]);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)), vertices.data(),
               GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buf.ids[1]);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)), indices.data(),
               GL_STATIC_DRAW);
  const GLsizei stride = 7 * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(6 * sizeof(float)));
  check_gl("prt geometry upload");
  const GLsizei n_indices = static_cast<GLsizei>(indices.size());

  // Sample basis values Y_i(w_s) (float) for the accumulation pass.
  std::vector<float> ylm(samples.ylm.begin(), samples.ylm.end());
  Buffer b_ylm(ylm.size() * sizeof(float), ylm.data());
  b_ylm.bind(0);

  // Render targets: G-buffer (2 colour + depth), depth map, accumulation.
  Textures tex(3 + 1 + static_cast<std::size_t>(passes * targets));
  const GLuint t_pos = tex.ids[0], t_nrm = tex.ids[1], t_gdepth = tex.ids[2], t_shadow = tex.ids[3];
  storage_2d(t_pos, GL_RGBA32F, W, H);
  storage_2d(t_nrm, GL_RGBA32F, W, H);
  storage_2d(t_gdepth, GL_DEPTH_COMPONENT32F, W, H);
  storage_2d(t_shadow, GL_DEPTH_COMPONENT32F, D, D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  for (int i = 0; i < passes * targets; ++i) storage_2d(tex.ids[4 + static_cast<std::size_t>(i)], GL_RGBA32F, W, H);
  check_gl("prt textures");
  Framebuffers fbo(2 + static_cast<std::size_t>(passes));
  std::vector<GLenum> draw(static_cast<std::size_t>(targets));
  for (int t = 0; t < targets; ++t) draw[static_cast<std::size_t>(t)] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(t);

  // 1. G-buffer from the camera. View coordinates (x, y, z) = ((p - eye).right, .up, .back);
  // clip = (x / (tan a), y / tan, depth, -z) with near/far bracketing the bounding sphere.
  {
    const glm::dvec3 eye = cam.eye - centre;
    const double dist = glm::length(eye);
    const double near_d = std::max(dist - radius, 1e-6 * radius), far_d = dist + radius;
    const Mat4 vp = camera_matrix(cam.right, cam.up, cam.back, cam.tan_half_fov, eye, W, H, near_d, far_d);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.ids[0]);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t_pos, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, t_nrm, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t_gdepth, 0);
    const GLenum g_draw[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, g_draw);
    check_framebuffer("G-buffer");
    glViewport(0, 0, W, H);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    gbuffer.use();
    gbuffer.set_mat4("view_proj", vp.m);
    glBindVertexArray(vao.ids[0]);
    glDrawElements(GL_TRIANGLES, n_indices, GL_UNSIGNED_INT, nullptr);
    check_gl("prt G-buffer pass");
  }

  // Depth-map and accumulation framebuffers.
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.ids[1]);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t_shadow, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  check_framebuffer("depth map");
  for (int g = 0; g < passes; ++g) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.ids[2 + static_cast<std::size_t>(g)]);
    for (int t = 0; t < targets; ++t)
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(t), GL_TEXTURE_2D,
                             tex.ids[4 + static_cast<std::size_t>(g * targets + t)], 0);
    glDrawBuffers(targets, draw.data());
    check_framebuffer("accumulation targets");
    const float zero[4] = {0, 0, 0, 0};
    for (int t = 0; t < targets; ++t) glClearBufferfv(GL_COLOR, t, zero);
  }
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, t_pos);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, t_nrm);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, t_shadow);
  glActiveTexture(GL_TEXTURE0);

  // Biases (see prt.hpp): depth units are 1 / (2 radius) per mesh unit.
  const double texel = 2.0 * radius / D;
  accumulate.set("coeffs", K);
  accumulate.set("visibility", opt.visibility ? 1 : 0);
  accumulate.set("normal_offset", static_cast<float>(opt.offset + 0.5 * texel));
  accumulate.set("depth_bias", static_cast<float>(opt.offset / (2.0 * radius) + 1e-6));
  accumulate.set("slope_bias", static_cast<float>(1.0 / D));

  glFinish();
  const auto t_loop = Clock::now();
  for (std::size_t s = 0; s < samples.dirs.size(); ++s) {
    const glm::dvec3 d = glm::normalize(samples.dirs[s]);
    const Mat4 lp = light_matrix(d, radius);  // depth = (radius - p.d) / (2 radius)
    if (opt.visibility) {
      glBindFramebuffer(GL_FRAMEBUFFER, fbo.ids[1]);
      glViewport(0, 0, D, D);
      glDisable(GL_BLEND);
      glEnable(GL_DEPTH_TEST);
      glClear(GL_DEPTH_BUFFER_BIT);
      depth.use();
      depth.set_mat4("light_proj", lp.m);
      glBindVertexArray(vao.ids[0]);
      glDrawElements(GL_TRIANGLES, n_indices, GL_UNSIGNED_INT, nullptr);
    }
    glViewport(0, 0, W, H);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    accumulate.use();
    accumulate.set_mat4("light_proj", lp.m);
    accumulate.set("direction", static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z));
    glBindVertexArray(vao.ids[1]);
    for (int g = 0; g < passes; ++g) {
      glBindFramebuffer(GL_FRAMEBUFFER, fbo.ids[2 + static_cast<std::size_t>(g)]);
      accumulate.set("first_channel", 4 * targets * g);
      accumulate.set("basis_offset", static_cast<int>(s) * K);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
  }
  glFinish();
  check_gl("prt accumulation");
  const double loop_s = std::chrono::duration<double>(Clock::now() - t_loop).count();
  glDisable(GL_BLEND);

  // Read back (GL rows start at the bottom; the result's row 0 is the top).
  const std::size_t np = static_cast<std::size_t>(W) * H;
  auto read = [&](GLuint fb, int attachment, std::vector<float>& out) {
    out.resize(np * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
    glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(attachment));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, out.data());
    check_gl("prt read-back");
  };
  std::vector<float> g_pos, g_nrm, acc;
  read(fbo.ids[0], 0, g_pos);
  read(fbo.ids[0], 1, g_nrm);
  PrtPixelResult r;
  r.width = W;
  r.height = H;
  r.bands = samples.bands;
  r.samples = static_cast<int>(samples.dirs.size());
  r.depth_resolution = opt.visibility ? D : 0;
  r.targets_per_pass = targets;
  r.passes_per_direction = passes;
  r.coeffs.assign(np * static_cast<std::size_t>(K), 0.0);
  r.ao.assign(np, 0.0);
  r.mask.assign(np, 0.0f);
  const double to_transfer = samples.weight / std::numbers::pi;
  auto dst = [&](std::size_t gl_index) {  // GL pixel -> result pixel
    const std::size_t row = static_cast<std::size_t>(H - 1) - gl_index / static_cast<std::size_t>(W);
    return row * static_cast<std::size_t>(W) + gl_index % static_cast<std::size_t>(W);
  };
  for (std::size_t p = 0; p < np; ++p) r.mask[dst(p)] = g_pos[4 * p + 3] != 0.0f ? 1.0f : 0.0f;
  for (int g = 0; g < passes; ++g)
    for (int t = 0; t < targets; ++t) {
      read(fbo.ids[2 + static_cast<std::size_t>(g)], t, acc);
      for (int k = 0; k < 4; ++k) {
        const int ch = 4 * (g * targets + t) + k;
        if (ch > K) break;
        for (std::size_t p = 0; p < np; ++p) {
          const std::size_t q = dst(p);
          if (r.mask[q] == 0.0f) continue;
          const double v = static_cast<double>(acc[4 * p + static_cast<std::size_t>(k)]) * to_transfer;
          if (ch == K)
            r.ao[q] = v;
          else
            r.coeffs[q * static_cast<std::size_t>(K) + static_cast<std::size_t>(ch)] = v * g_nrm[4 * p + 3];
        }
      }
    }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  r.seconds_per_direction = loop_s / static_cast<double>(samples.dirs.size());
  return r;
}

}  // namespace atmosh::gpu
