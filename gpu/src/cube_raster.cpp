// Cube maps of a mesh's surface radiance rasterised at many centres (see cube_raster.hpp).
#include "atmosh/gpu/cube_raster.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/vec3.hpp>

#include "atmosh/gpu/program.hpp"
#include "gl_objects.hpp"


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
// Draws the six faces of centres [first, first + count) into the bound atlas (face f of the
// k-th at (f N, k N)); the program is current, the mesh's vertex array bound.
void draw_batch(const Program& prog, const CubeRasterMesh& mesh, const std::vector<std::array<double, 3>>& centres,
                std::size_t first, int count, int N, GLsizei n_indices);

// Checks a cube-raster mesh, its centres and options (std::invalid_argument).
void check_cube_input(const CubeRasterMesh& mesh, const std::vector<std::array<double, 3>>& centres,
                      const CubeRasterOptions& opt) {
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
}

// Uploads the mesh into vao/vbo/ibo (attributes 0..3: position, normal, front, back).
void upload_cube_mesh(const CubeRasterMesh& mesh, const Vao& vao, const Vbo& vbo, const Vbo& ibo) {
  glBindVertexArray(vao.id);
  glBindBuffer(GL_ARRAY_BUFFER, vbo.id);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(mesh.vertices.size(), 1) * sizeof(float)),
               mesh.vertices.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo.id);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER,
               static_cast<GLsizeiptr>(std::max<std::size_t>(mesh.indices.size(), 1) * sizeof(std::uint32_t)),
               mesh.indices.data(), GL_STATIC_DRAW);
  const GLsizei stride = kCubeRasterVertexFloats * sizeof(float);
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexAttribArray(a);
    glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * a * sizeof(float)));
  }
  check_gl("cube raster geometry upload");
}

// Centres a batch: as many as the largest texture (and 4096 rows) allow.
int cube_batch(int N, std::size_t nc) {
  GLint max_size = 4096;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
  if (6 * N > max_size) throw std::invalid_argument("render_cube_maps: 6 x size exceeds the largest texture");
  return static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(nc, std::min(max_size, 4096) / N)));
}
}  // namespace

namespace {
void draw_batch(const Program& prog, const CubeRasterMesh& mesh, const std::vector<std::array<double, 3>>& centres,
                std::size_t first, int count, int N, GLsizei n_indices) {
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
}
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
  check_cube_input(mesh, centres, opt);
  const int N = opt.size;
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
  Fbo fbo;
  detail::colour_depth_target(fbo.id, colour.id, depth.id, W, H, "the probe cube maps");
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
    draw_batch(prog, mesh, centres, first, count, N, n_indices);
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
  Tex colour, depth, background;
  Fbo fbo;
  int width = 0, height = 0;
  GLsizei n_indices = 0;
  bool has_background = false;
  // The draw of draw() and draw_resident(): the target bound with the fixed state (no blending,
  // culling or scissor; depth test LESS), its colour started from the background (`from_background`
  // and one is set) or 0, depth cleared to 1, the mesh drawn with `program`.
  void draw_mesh(const Program& program, bool from_background, const char* what) const;
  // The target's RGBA read back, row 0 at the top.
  std::vector<float> read_back(const char* what) const;
};

void MeshRaster::Impl::draw_mesh(const Program& program, bool from_background, const char* what) const {
  ctx->make_current();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id);
  glViewport(0, 0, width, height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  if (from_background && has_background) {
    glCopyImageSubData(background.id, GL_TEXTURE_2D, 0, 0, 0, 0, colour.id, GL_TEXTURE_2D, 0, 0, 0, 0, width, height, 1);
  } else {
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
  }
  const float one = 1.0f;
  glClearBufferfv(GL_DEPTH, 0, &one);
  program.use();
  glBindVertexArray(vao.id);
  if (n_indices > 0) glDrawElements(GL_TRIANGLES, n_indices, GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  check_gl(what);
}

std::vector<float> MeshRaster::Impl::read_back(const char* what) const {
  ctx->make_current();
  const std::size_t np = static_cast<std::size_t>(width) * height;
  std::vector<float> gl(np * 4), out(np * 4);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, gl.data());
  check_gl(what);
  for (int r = 0; r < height; ++r)  // GL rows start at the bottom
    std::copy(&gl[static_cast<std::size_t>(height - 1 - r) * width * 4],
              &gl[static_cast<std::size_t>(height - r) * width * 4], &out[static_cast<std::size_t>(r) * width * 4]);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return out;
}

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
  detail::colour_depth_target(m.fbo.id, m.colour.id, m.depth.id, width, height, "render_mesh_rgba");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("render_mesh_rgba setup");
}

MeshRaster::~MeshRaster() = default;

std::vector<float> MeshRaster::draw(const Program& program) const {
  impl_->draw_mesh(program, false, "render_mesh_rgba draw");
  return impl_->read_back("render_mesh_rgba read-back");
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

void MeshRaster::set_background(const std::vector<float>& rgba) {
  Impl& m = *impl_;
  const std::size_t np = static_cast<std::size_t>(m.width) * m.height;
  if (rgba.size() != np * 4) throw std::invalid_argument("MeshRaster::set_background: need RGBA per pixel");
  m.ctx->make_current();
  std::vector<float> gl(np * 4);
  for (int r = 0; r < m.height; ++r)  // GL rows start at the bottom
    std::copy(&rgba[static_cast<std::size_t>(m.height - 1 - r) * m.width * 4],
              &rgba[static_cast<std::size_t>(m.height - r) * m.width * 4], &gl[static_cast<std::size_t>(r) * m.width * 4]);
  if (!m.has_background) {
    glBindTexture(GL_TEXTURE_2D, m.background.id);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, m.width, m.height);
    m.has_background = true;
  }
  glBindTexture(GL_TEXTURE_2D, m.background.id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, m.width, m.height, GL_RGBA, GL_FLOAT, gl.data());
  check_gl("MeshRaster background upload");
}

void MeshRaster::draw_resident(const Program& program) const { impl_->draw_mesh(program, true, "MeshRaster resident draw"); }

std::vector<float> MeshRaster::read() const { return impl_->read_back("MeshRaster read-back"); }

// ---- ProbeProjector ----

struct ProbeProjector::Impl {
  const Context* ctx = nullptr;
  CubeRasterMesh mesh;
  std::vector<std::array<double, 3>> centres;
  CubeRasterOptions opt;
  int supersample = 1, max_bands = 1, stride = 1, batch = 1;
  std::unique_ptr<Program> raster, project;
  Vao vao;
  Vbo vbo, ibo;
  Tex colour, depth;
  Fbo fbo;
  std::unique_ptr<Buffer> env, sh, texel_int;
};

ProbeProjector::ProbeProjector(const Context& ctx, const CubeRasterMesh& mesh,
                               const std::vector<std::array<double, 3>>& centres, const CubeRasterOptions& opt,
                               int supersample, const std::vector<float>& env, int max_bands, int stride) {
  check_cube_input(mesh, centres, opt);
  const int NS = opt.size;
  if (supersample < 1 || NS % supersample != 0)
    throw std::invalid_argument("ProbeProjector: the supersample must divide the cube size");
  if (max_bands < 1 || max_bands > 16) throw std::invalid_argument("ProbeProjector: bands must be in 1..16");
  if (stride < max_bands * max_bands) throw std::invalid_argument("ProbeProjector: stride below bands^2");
  if (env.size() != static_cast<std::size_t>(6) * NS * NS * 3)
    throw std::invalid_argument("ProbeProjector: the environment needs 3 floats per texel");
  if (centres.empty()) throw std::invalid_argument("ProbeProjector: no centres");
  ctx.make_current();
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.ctx = &ctx;
  m.mesh = mesh;
  m.centres = centres;
  m.opt = opt;
  m.supersample = supersample;
  m.max_bands = max_bands;
  m.stride = stride;
  m.raster = std::make_unique<Program>(std::vector<ShaderPart>{embedded_source("gpu/shaders/gi_probe_cube.vert")},
                                       std::vector<ShaderPart>{embedded_source("gpu/shaders/gi_probe_cube.frag")});
  m.project = std::make_unique<Program>(
      std::vector<ShaderPart>{embedded_source("libsh/include/atmosh/sh/shared/cube.glsl.hpp"),
                              embedded_source("gpu/shaders/gi_probe_project.comp")});
  upload_cube_mesh(mesh, m.vao, m.vbo, m.ibo);
  glBindVertexArray(0);
  m.batch = cube_batch(NS, centres.size());
  const int W = 6 * NS, H = m.batch * NS;
  detail::colour_depth_target(m.fbo.id, m.colour.id, m.depth.id, W, H, "the probe projector");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m.env = std::make_unique<Buffer>(env.size() * sizeof(float), env.data());
  const std::vector<float> zero(centres.size() * 3 * static_cast<std::size_t>(stride), 0.0f);
  m.sh = std::make_unique<Buffer>(zero.size() * sizeof(float), zero.data());
  const std::size_t n = static_cast<std::size_t>(NS / supersample);
  m.texel_int = std::make_unique<Buffer>(static_cast<std::size_t>(m.batch) * 6 * n * n * 3 * sizeof(float));
  check_gl("probe projector setup");
}

ProbeProjector::~ProbeProjector() = default;

void ProbeProjector::run(int bands, const std::vector<double>& window, const ProbeSun& sun, double* split) const {
  const Impl& m = *impl_;
  if (bands < 1 || bands > m.max_bands) throw std::invalid_argument("ProbeProjector::run: bands out of range");
  if (!window.empty() && window.size() < static_cast<std::size_t>(bands))
    throw std::invalid_argument("ProbeProjector::run: one window weight per band");
  m.ctx->make_current();
  const int NS = m.opt.size, W = 6 * NS;
  const std::size_t nc = m.centres.size();
  const double a = (m.opt.far + m.opt.near) / (m.opt.far - m.opt.near),
               b = -2.0 * m.opt.far * m.opt.near / (m.opt.far - m.opt.near);
  m.raster->use();
  m.raster->set("depth_a", static_cast<float>(a));
  m.raster->set("depth_b", static_cast<float>(b));
  m.project->use();
  m.project->set("atlas", 0);
  m.project->set("ns", NS);
  m.project->set("ss", m.supersample);
  m.project->set("bands", bands);
  m.project->set("stride", m.stride);
  for (int l = 0; l < 16; ++l) {
    const std::string name = "window[" + std::to_string(l) + "]";
    m.project->set(name.c_str(), static_cast<float>(l < bands && !window.empty() ? window[static_cast<std::size_t>(l)] : 1.0));
  }
  m.project->set("include_sun", sun.on ? 1 : 0);
  m.project->set("sun_dir", static_cast<float>(sun.direction[0]), static_cast<float>(sun.direction[1]),
                 static_cast<float>(sun.direction[2]));
  m.project->set("sun_e", static_cast<float>(sun.irradiance[0]), static_cast<float>(sun.irradiance[1]),
                 static_cast<float>(sun.irradiance[2]));
  m.env->bind(0);
  m.sh->bind(1);
  m.texel_int->bind(2);
  const int N = NS / m.supersample;
  const GLsizei n_indices = static_cast<GLsizei>(m.mesh.indices.size());
  if (split != nullptr) split[0] = split[1] = 0;
  auto t_lap = Clock::now();
  auto lap = [&](int k) {
    if (split == nullptr) return;
    glFinish();
    const auto t = Clock::now();
    split[k] += std::chrono::duration<double>(t - t_lap).count();
    t_lap = t;
  };
  for (std::size_t first = 0; first < nc; first += static_cast<std::size_t>(m.batch)) {
    const int count = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(m.batch), nc - first));
    // 1. the batch's cube maps into the atlas
    glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.id);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, W, count * NS);
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
    const float one = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &one);
    m.raster->use();
    glBindVertexArray(m.vao.id);
    if (n_indices > 0) draw_batch(*m.raster, m.mesh, m.centres, first, count, NS, n_indices);
    glBindVertexArray(0);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    lap(0);
    // 2. its projection (reads the atlas as a texture; the next batch's draws wait for it)
    m.project->use();
    m.project->set("count", count);
    m.project->set("first", static_cast<int>(first));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, m.colour.id);
    m.project->set("stage", 0);
    glDispatchCompute(static_cast<unsigned>((static_cast<std::size_t>(count) * 6 * N * N + 63) / 64), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    m.project->set("stage", 1);
    glDispatchCompute(static_cast<unsigned>((static_cast<std::size_t>(count) * bands * bands + 63) / 64), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
    lap(1);
  }
  glBindTexture(GL_TEXTURE_2D, 0);
  check_gl("probe projector run");
}

void ProbeProjector::bind_sh(unsigned binding) const { impl_->sh->bind(binding); }

std::vector<float> ProbeProjector::read_sh() const {
  impl_->ctx->make_current();
  std::vector<float> out(impl_->sh->bytes() / sizeof(float));
  impl_->sh->download(out.data(), out.size() * sizeof(float));
  return out;
}

int ProbeProjector::stride() const { return impl_->stride; }
std::size_t ProbeProjector::probes() const { return impl_->centres.size(); }

// ---- SunShadowMap ----

struct SunShadowMap::Impl {
  const Context* ctx = nullptr;
  double radius = 1;
  int resolution = 1;
  GLsizei count = 0;
  Vao vao;
  Vbo vbo;
  Tex depth;
  Fbo fbo;
  std::unique_ptr<Program> prog;
  mutable detail::Mat4 lp;
};

SunShadowMap::SunShadowMap(const Context& ctx, const std::vector<float>& positions, double radius, int resolution) {
  if (resolution < 16 || resolution > 16384) throw std::invalid_argument("SunShadowMap: resolution must be in 16..16384");
  if (positions.size() % 9 != 0) throw std::invalid_argument("SunShadowMap: a triangle soup of 3 floats a vertex");
  if (!(radius > 0) || !std::isfinite(radius)) throw std::invalid_argument("SunShadowMap: radius must be positive");
  ctx.make_current();
  impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.ctx = &ctx;
  m.radius = radius;
  m.resolution = resolution;
  m.count = static_cast<GLsizei>(positions.size() / 3);
  m.prog = std::make_unique<Program>(detail::parts("gpu/shaders/prt_depth.vert"), detail::parts("gpu/shaders/prt_depth.frag"));
  glBindVertexArray(m.vao.id);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo.id);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(positions.size(), 1) * sizeof(float)),
               positions.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glBindVertexArray(0);
  detail::storage_2d(m.depth.id, GL_DEPTH_COMPONENT32F, resolution, resolution);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.id);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, m.depth.id, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  detail::check_framebuffer("sun shadow map");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("sun shadow map setup");
}

SunShadowMap::~SunShadowMap() = default;

void SunShadowMap::render(const std::array<double, 3>& direction) const {
  const Impl& m = *impl_;
  const glm::dvec3 s(direction[0], direction[1], direction[2]);
  const double len = glm::length(s);
  if (!(len > 0) || !std::isfinite(len)) throw std::invalid_argument("SunShadowMap: the sun's direction must be non-zero");
  m.ctx->make_current();
  m.lp = detail::light_matrix(s / len, m.radius);
  glBindFramebuffer(GL_FRAMEBUFFER, m.fbo.id);
  glViewport(0, 0, m.resolution, m.resolution);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  m.prog->use();
  m.prog->set_mat4("light_proj", m.lp.m);
  glBindVertexArray(m.vao.id);
  if (m.count > 0) glDrawArrays(GL_TRIANGLES, 0, m.count);
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  check_gl("sun shadow map pass");
}

void SunShadowMap::bind(unsigned unit, float light_proj[16]) const {
  const Impl& m = *impl_;
  glActiveTexture(GL_TEXTURE0 + unit);
  glBindTexture(GL_TEXTURE_2D, m.depth.id);
  glActiveTexture(GL_TEXTURE0);
  std::copy(m.lp.m, m.lp.m + 16, light_proj);
}

int SunShadowMap::resolution() const { return impl_->resolution; }
double SunShadowMap::radius() const { return impl_->radius; }

}  // namespace atmosh::gpu
