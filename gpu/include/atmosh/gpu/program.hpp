// atmosh/gpu/program.hpp — GLSL compute (and vertex + fragment) programs assembled from the shared
// C++/GLSL sources, and shader storage buffers.
//
// Sources. The build (cmake/AtmoshEmbedGlsl.cmake) embeds, for each shared
// header (*.glsl.hpp under libatmo/include/atmosh/atmo/shared/) the block
// between its ATMOSH_GLSL_BEGIN / ATMOSH_GLSL_END markers with "glm::" deleted,
// and each shader under gpu/shaders/ whole. embedded_source(path) returns one by
// its repository-relative path. A Program is compiled from a list of such parts
// in order, after a preamble
//     #version 430 core
//     #define real float
//     #define real3 vec3
//     #define ATMOSH_FN
//     #define ATMOSH_GLSL 1
//     <extra defines>
// and every part is preceded by "#line <its first line> <its index + 1>", so the
// driver's messages name source-string numbers that map back to files.
//
// Errors. A compile or link failure throws ShaderError whose what() is the
// driver log with every location rewritten as "path:line" of the shared source
// (Mesa "N:L(C):" and NVIDIA "N(L) :" formats are recognised; other lines are
// kept as they are). Requires a current Context (gpu/context.hpp).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace atmosh::gpu {

class ShaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One piece of GLSL source: `path` names it in messages, `first_line` is the
// line of `text`'s first line in that file.
struct ShaderPart {
  std::string path;
  int first_line = 1;
  std::string text;
};

// An embedded source by repository-relative path, e.g.
// "libatmo/include/atmosh/atmo/shared/geometry.glsl.hpp" or
// "gpu/shaders/sky.comp". std::out_of_range if it is not embedded.
ShaderPart embedded_source(const std::string& path);
std::vector<std::string> embedded_source_paths();

// A part that redefines `real` ("float" or "double") for the parts after it, so
// that a shared block pasted again after it adds overloads in that precision.
ShaderPart real_type_part(const std::string& type);

// Rewrites driver locations "N:L(C)" / "N(L)" with part N-1's path and line L
// (N = 0 is the preamble and is reported as "<preamble>").
std::string map_shader_log(const std::string& log, const std::vector<ShaderPart>& parts);

class Program {
 public:
  // Compiles and links a compute shader. Throws ShaderError (mapped log).
  explicit Program(const std::vector<ShaderPart>& parts, const std::string& defines = "");
  // Compiles and links a vertex + fragment program (rasterisation passes); each
  // stage gets the same preamble and its own part numbering.
  Program(const std::vector<ShaderPart>& vertex, const std::vector<ShaderPart>& fragment,
          const std::string& defines = "");
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  void use() const;
  unsigned id() const { return id_; }
  // Uniform location (-1 if the uniform is absent or optimised away).
  int uniform(const char* name) const;
  // Byte offset of a shader-storage block member ("params.n_q[0]") in the driver's
  // layout (program interface query); -1 if the program has no such variable.
  int buffer_variable_offset(const char* name) const;
  void set(const char* name, int v) const;
  void set(const char* name, unsigned v) const;
  void set(const char* name, float v) const;
  void set(const char* name, float x, float y, float z) const;
  void set_double(const char* name, double v) const;
  void set_mat4(const char* name, const float* column_major) const;
  // glDispatchCompute + a barrier making shader-storage writes visible to
  // buffer read-back.
  void dispatch(unsigned gx, unsigned gy = 1, unsigned gz = 1) const;

 private:
  unsigned id_ = 0;
};

// A shader storage buffer (std430). Contents are raw bytes; use float/int data.
class Buffer {
 public:
  explicit Buffer(std::size_t bytes, const void* data = nullptr);
  ~Buffer();
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  void bind(unsigned binding) const;
  void upload(const void* data, std::size_t bytes, std::size_t offset = 0);
  // Every byte zero, on the device (nothing copied from the host). The size must be a
  // multiple of 4.
  void clear();
  void download(void* data, std::size_t bytes, std::size_t offset = 0) const;
  std::size_t bytes() const { return bytes_; }

 private:
  unsigned id_ = 0;
  std::size_t bytes_ = 0;
};

// Throws std::runtime_error naming `what` if glGetError reports an error.
void check_gl(const char* what);
// Blocks until every GL command issued so far has completed (glFinish): for timing
// GPU work, whose dispatches return before they run.
void finish();

}  // namespace atmosh::gpu
