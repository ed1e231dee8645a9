// Cube maps of a mesh's surface radiance rasterised at many centres (see cube_raster.hpp).
#include "atmosh/gpu/cube_raster.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "atmosh/gpu/program.hpp"


namespace atmosh::gpu {

namespace {
using Clock = std::chrono::steady_clock;

// RAII holders of one GL name each.
struct Tex {
  GLuint id = 0;
  Tex() { glGenTextures(1, &id); }
  ~Tex() { glDeleteTextures(1, &id); }
  Tex(const Tex&) = delete;
  Tex& operator=(const Tex&) = delete;
};
struct Fbo {
  GLuint id = 0;
  Fbo() { glGenFramebuffers(1, &id); }
  ~Fbo() { glDeleteFramebuffers(1, &id); }
  Fbo(const Fbo&) = delete;
  Fbo& operator=(const Fbo&) = delete;
};
struct Vbo {
  GLuint id = 0;
  Vbo() { glGenBuffers(1, &id); }
  ~Vbo() { glDeleteBuffers(1, &id); }
  Vbo(const Vbo&) = delete;
  Vbo& operator=(const Vbo&) = delete;
};
struct Vao {
  GLuint id = 0;
  Vao() { glGenVertexArrays(1, &id); }
  ~Vao() { glDeleteVertexArrays(1, &id); }
  Vao(const Vao&) = delete;
  Vao& operator=(const Vao&) = delete;
};
}  // namespace

void cube_face_frame(int face, std::array<double, 3>& u, std::array<double, 3>& v, std::array<double, 3>& w) {
  // libsh's face_direction(f, u, v): +X (1, -v, -u), -X (-1, -v, u), +Y (u, 1, v), -Y (u, -1, -v),
  // +Z (u, -v, 1), -Z (-u, -v, -1).
  switch (face) {
    case 0: u = {0, 0, -1}, v = {0, -1, 0}, w = {1, 0, 0}; break;
    case 1: u = {0, 0, 1}, v = {0, -1, 0}, w = {-1, 0, 0}; break;
    case 2: u = {1, 0, 0}, v = {0, 0, 1}, w = {0, 1, 0}; break;
    case 3: u = {1, 0, 0}, v = {0, 0, -1}, w = {0, -1, 0}; break;
    case 4: u = {1, 0, 0}, v = {0, -1, 0}, w = {0, 0, 1}; break;
    case 5: u = {-1, 0, 0}, v = {0, -1, 0}, w = {0, 0, -1}; break;
    default: throw std::invalid_argument("cube_face_frame: face must be 0..5, got " + std::to_string(face));
  }
}

CubeRasterResult render_cube_maps(const Context& ctx, const CubeRasterMesh& mesh,
                                  const std::vector<std::array<double, 3>>& centres, const CubeRasterOptions& opt) {
  const int N = opt.size;
  if (N < 1 || N > 2048) throw std::invalid_argument("render_cube_maps: size must be in 1..2048, got " + std::to_string(N));
  if (!(opt.near > 0) || !(opt.far > opt.near) || !std::isfinite(opt.far))
    throw std::invalid_argument("render_cube_maps: need 0 < near < far (finite)");
  if (mesh.vertices.size() % kCubeRasterVertexFloats != 0 || mesh.indices.size() % 3 != 0)
    throw std::invalid_argument("render_cube_maps: vertex or index array of the wrong length");
  const std::size_t nv = mesh.vertices.size() / kCubeRasterVertexFloats;
  for (std::uint32_t i : mesh.indices)
    if (i >= nv) throw std::invalid_argument("render_cube_maps: triangle index out of range");
  for (const auto& c : centres)
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
      throw std::invalid_argument("render_cube_maps: non-finite centre");
  ctx.make_current();
  const Program prog({embedded_source("gpu/shaders/gi_probe_cube.vert")}, {embedded_source("gpu/shaders/gi_probe_cube.frag")});
  const auto t0 = Clock::now();
  CubeRasterResult r;
  r.size = N;
  const std::size_t nc = centres.size();
  const std::size_t face_texels = static_cast<std::size_t>(N) * N;
  r.texels.assign(nc * 6 * face_texels * 4, 0.0f);
  if (nc == 0 || mesh.indices.empty()) return r;

  Vao vao;
  Vbo vbo, ibo;
  glBindVertexArray(vao.id);
  glBindBuffer(GL_ARRAY_BUFFER, vbo.id);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.vertices.size() * sizeof(float)), mesh.vertices.data(),
               GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo.id);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(std::uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  const GLsizei stride = kCubeRasterVertexFloats * sizeof(float);
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * a * sizeof(float)));
  }
  check_gl("cube raster geometry upload");

  // Atlas: face f of the b-th centre of a batch at (f N, b N); as many centres a batch as
  // the largest texture (and 4096 rows) allow.
  GLint max_size = 4096;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (6 * N > max_size) throw std::invalid_argument("render_cube_maps: 6 x size exceeds the largest texture");
  const int batch = static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(nc, std::min(max_size, 4096) / N)));
  const int W = 6 * N, H = batch * N;
  Tex colour, depth;
  glBindTexture(GL_TEXTURE_2D, colour.id);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, W, H);
  glBindTexture(GL_TEXTURE_2D, depth.id);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, W, H);
  Fbo fbo;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour.id, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth.id, 0);
  const GLenum draw = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &draw);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("OpenGL framebuffer incomplete in the probe cube maps");
  check_gl("cube raster targets");

  prog.use();
  // depth: z_ndc = (a w + b) / w maps w = near -> -1, far -> +1
  const double a = (opt.far + opt.near) / (opt.far - opt.near), b = -2.0 * opt.far * opt.near / (opt.far - opt.near);
  prog.set("depth_a", static_cast<float>(a));
  prog.set("depth_b", static_cast<float>(b));
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_SCISSOR_TEST);
  const GLsizei n_indices = static_cast<GLsizei>(mesh.indices.size());
  std::vector<float> atlas(static_cast<std::size_t>(W) * H * 4);
  for (std::size_t first = 0; first < nc; first += static_cast<std::size_t>(batch)) {
    const int count = static_cast<int>(std::min<std::size_t>(batch, nc - first));
    glScissor(0, 0, W, H);
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    const float one = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &one);
    for (int k = 0; k < count; ++k) {
      const auto& c = centres[first + static_cast<std::size_t>(k)];
      prog.set("probe", static_cast<float>(c[0] - mesh.origin[0]), static_cast<float>(c[1] - mesh.origin[1]),
               static_cast<float>(c[2] - mesh.origin[2]));
      for (int f = 0; f < 6; ++f) {
        std::array<double, 3> fu, fv, fw;
        cube_face_frame(f, fu, fv, fw);
        prog.set("face_u", static_cast<float>(fu[0]), static_cast<float>(fu[1]), static_cast<float>(fu[2]));
        prog.set("face_v", static_cast<float>(fv[0]), static_cast<float>(fv[1]), static_cast<float>(fv[2]));
        prog.set("face_w", static_cast<float>(fw[0]), static_cast<float>(fw[1]), static_cast<float>(fw[2]));
        glViewport(f * N, k * N, N, N);
        glScissor(f * N, k * N, N, N);
        glDrawElements(GL_TRIANGLES, n_indices, GL_UNSIGNED_INT, nullptr);
      }
    }
    check_gl("cube raster draws");
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, W, count * N, GL_RGBA, GL_FLOAT, atlas.data());
    check_gl("cube raster read-back");
    // GL row y = k N + r (window y = v: row r of libsh's face is GL row r of the viewport).
    for (int k = 0; k < count; ++k)
      for (int f = 0; f < 6; ++f)
        for (int row = 0; row < N; ++row) {
          const float* src = &atlas[(static_cast<std::size_t>(k * N + row) * W + static_cast<std::size_t>(f * N)) * 4];
          float* dst = &r.texels[(((first + static_cast<std::size_t>(k)) * 6 + static_cast<std::size_t>(f)) * face_texels +
                                  static_cast<std::size_t>(row) * N) * 4];
          std::copy(src, src + static_cast<std::size_t>(N) * 4, dst);
        }
  }
  glDisable(GL_SCISSOR_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  r.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

struct MeshRaster::Impl {
  const Context* ctx = nullptr;
  Vao vao;
  Vbo vbo, ibo;
  Tex colour, depth;
  Fbo fbo;
  int width = 0, height = 0;
  GLsizei n_indices = 0;
};

MeshRaster::MeshRaster(const Context& ctx, const std::vector<float>& vertices, const std::vector<int>& attribute_sizes,
                       const std::vector<std::uint32_t>& indices, int width, int height) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("render_mesh_rgba: bad image size");
  int stride_floats = 0;
  for (int a : attribute_sizes) {
    if (a < 1 || a > 4) throw std::invalid_argument("render_mesh_rgba: attribute sizes must be 1..4");
    stride_floats += a;
  }
  if (stride_floats == 0 || vertices.size() % static_cast<std::size_t>(stride_floats) != 0 || indices.size() % 3 != 0)
    throw std::invalid_argument("render_mesh_rgba: vertex or index array of the wrong length");
  const std::size_t nv = vertices.size() / static_cast<std::size_t>(stride_floats);
  for (std::uint32_t i : indices)
    if (i >= nv) throw std::invalid_argument("render_mesh_rgba: triangle index out of range");
  ctx.make_current();
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.ctx = &ctx;
  m.width = width;
  m.height = height;
  m.n_indices = static_cast<GLsizei>(indices.size());
  glBindVertexArray(m.vao.id);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo.id);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(vertices.size(), 1) * sizeof(float)),
               vertices.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.ibo.id);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(indices.size(), 1) * sizeof(std::uint32_t)),
               indices.data(), GL_STATIC_DRAW);
  int offset = 0;
  for (std::size_t a = 0; a < attribute_sizes.size(); ++a) {
    glEnableVertexAttribArray(static_cast<GLuint>(a));
    glVertexAttribPointer(static_cast<GLuint>(a), attribute_sizes[a], GL_FLOAT, GL_FALSE,
                          static_cast<GLsizei>(stride_floats * sizeof(float)),
                          reinterpret_cast<const void*>(static_cast<std::size_t>(offset) * sizeof(float)));
    offset += attribute_sizes[a];
  }
  glBindVertexArray(0);
  glBindTexture(GL_TEXTURE_2D, m.colour.id);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, width, height);
  glBindTexture(GL_TEXTURE_2D, m.depth.id);
  glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.id);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, m.colour.id, 0);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, m.depth.id, 0);
  const GLenum draw = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &draw);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("OpenGL framebuffer incomplete in render_mesh_rgba");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("render_mesh_rgba setup");
}

MeshRaster::~MeshRaster() = default;

std::vector<float> MeshRaster::draw(const Program& program) const {
  const Impl& m = *impl_;
  m.ctx->make_current();
  const int width = m.width, height = m.height;
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.id);
  glViewport(0, 0, width, height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  const float one = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &one);
  program.use();
  glBindVertexArray(m.vao.id);
  if (m.n_indices > 0) glDrawElements(GL_TRIANGLES, m.n_indices, GL_UNSIGNED_INT, nullptr);
  check_gl("render_mesh_rgba draw");
  const std::size_t np = static_cast<std::size_t>(width) * height;
  std::vector<float> gl(np * 4), out(np * 4);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, gl.data());
  check_gl("render_mesh_rgba read-back");
  for (int r = 0; r < height; ++r)  // GL rows start at the bottom
    std::copy(&gl[static_cast<std::size_t>(height - 1 - r) * width * 4],
              &gl[static_cast<std::size_t>(height - r) * width * 4], &out[static_cast<std::size_t>(r) * width * 4]);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glBindVertexArray(0);
  return out;
}

std::vector<float> render_mesh_rgba(const Context& ctx, const Program& program, const std::vector<float>& vertices,
                                    const std::vector<int>& attribute_sizes, const std::vector<std::uint32_t>& indices,
                                    int width, int height, double* seconds) {
  const auto t0 = Clock::now();
  const MeshRaster r(ctx, vertices, attribute_sizes, indices, width, height);
  std::vector<float> out = r.draw(program);
  if (seconds != nullptr) *seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return out;
}

}  // namespace atmosh::gpu
