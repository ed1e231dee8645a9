#include "atmosh/gpu/program.hpp"
#include "embedded_sources.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <regex>
#include <sstream>

namespace atmosh::gpu {

ShaderPart embedded_source(const std::string& path) {
  for (int i = 0; i < detail::kEmbeddedSourceCount; ++i) {
    const auto& e = detail::kEmbeddedSources[i];
    if (path == e.path) return ShaderPart{e.path, e.first_line, e.text};
  }
  throw std::out_of_range("no embedded GLSL source " + path);
}

std::vector<std::string> embedded_source_paths() {
  std::vector<std::string> p;
  for (int i = 0; i < detail::kEmbeddedSourceCount; ++i) p.emplace_back(detail::kEmbeddedSources[i].path);
  return p;
}

// The GLSL side of the shared headers' `using real`, `real3`, `real_array`, ATMOSH_GET and
// ATMOSH_PUT: in double, arrays indexed at run time hold packed uvec2 (view_ray.glsl.hpp).
static std::string real_type_defines(const std::string& type) {
  const std::string vec3 = type == "double" ? "dvec3" : type == "float" ? "vec3" : type + "3";
  const bool packed = type == "double";
  return "#undef real\n#define real " + type + "\n#undef real3\n#define real3 " + vec3 +
         "\n#undef real_array\n#define real_array " + (packed ? "uvec2" : type) +
         "\n#undef ATMOSH_GET\n#define ATMOSH_GET(a, i) " + (packed ? "packDouble2x32((a)[i])" : "(a)[i]") +
         "\n#undef ATMOSH_PUT\n#define ATMOSH_PUT(v) " + (packed ? "unpackDouble2x32(v)" : "(v)") + "\n";
}

ShaderPart real_type_part(const std::string& type) {
  return ShaderPart{"<real = " + type + ">", 1, real_type_defines(type)};
}

std::string map_shader_log(const std::string& log, const std::vector<ShaderPart>& parts) {
  // Mesa: "0:12(5): error: ..."; NVIDIA: "0(12) : error C1008: ...".
  static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):?)");
  static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:?)");
  auto name = [&](int id) {
    if (id == 0) return std::string("<preamble>");
    if (id >= 1 && id <= static_cast<int>(parts.size())) return parts[static_cast<std::size_t>(id - 1)].path;
    return "<source " + std::to_string(id) + ">";
  };
  std::istringstream in(log);
  std::ostringstream out;
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::smatch m;
    std::string mapped = line;
    if (std::regex_search(line, m, mesa))
      mapped = name(std::stoi(m[1])) + ":" + m[2].str() + ":" + m[3].str() + ":" + m.suffix().str();
    else if (std::regex_search(line, m, nvidia))
      mapped = name(std::stoi(m[1])) + ":" + m[2].str() + ":" + m.suffix().str();
    if (!first) out << '\n';
    out << mapped;
    first = false;
  }
  return out.str();
}

void finish() { glFinish(); }

void check_gl(const char* what) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%04x", e);
    throw std::runtime_error(std::string("OpenGL error ") + buf + " in " + what);
  }
}

namespace {
std::string assemble(const std::vector<ShaderPart>& parts, const std::string& defines) {
  std::string src = "#version 430 core\n" + real_type_defines("float") + "#define ATMOSH_FN\n#define ATMOSH_GLSL 1\n";
  src += defines;
  if (!src.empty() && src.back() != '\n') src += '\n';
  for (std::size_t i = 0; i < parts.size(); ++i) {
    src += "#line " + std::to_string(parts[i].first_line) + " " + std::to_string(i + 1) + "\n";
    src += parts[i].text;
    if (!parts[i].text.empty() && parts[i].text.back() != '\n') src += '\n';
  }
  return src;
}

// Compiles one stage; throws ShaderError with the mapped log.
GLuint compile_stage(GLenum stage, const char* stage_name, const std::vector<ShaderPart>& parts,
                     const std::string& defines) {
  const std::string src = assemble(parts, defines);
  const GLuint sh = glCreateShader(stage);
  if (!sh) throw ShaderError(std::string("glCreateShader(") + stage_name + ") failed (no current OpenGL 4.3 context?)");
  const char* p = src.c_str();
  glShaderSource(sh, 1, &p, nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    glGetShaderInfoLog(sh, n, nullptr, log.data());
    glDeleteShader(sh);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    throw ShaderError("GLSL compile error:\n" + map_shader_log(log, parts));
  }
  return sh;
}

// Links the stages into a program (deleting them); throws ShaderError with the log
// mapped through `parts` (the last stage's parts).
GLuint link_program(const std::vector<GLuint>& stages, const std::vector<ShaderPart>& parts) {
  const GLuint id = glCreateProgram();
  for (GLuint sh : stages) glAttachShader(id, sh);
  glLinkProgram(id);
  for (GLuint sh : stages) glDeleteShader(sh);
  GLint ok = 0;
  glGetProgramiv(id, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    glGetProgramiv(id, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    glGetProgramInfoLog(id, n, nullptr, log.data());
    glDeleteProgram(id);
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    throw ShaderError("GLSL link error:\n" + map_shader_log(log, parts));
  }
  return id;
}
}  // namespace

Program::Program(const std::vector<ShaderPart>& parts, const std::string& defines) {
  id_ = link_program({compile_stage(GL_COMPUTE_SHADER, "GL_COMPUTE_SHADER", parts, defines)}, parts);
}

Program::Program(const std::vector<ShaderPart>& vertex, const std::vector<ShaderPart>& fragment,
                 const std::string& defines) {
  const GLuint vs = compile_stage(GL_VERTEX_SHADER, "GL_VERTEX_SHADER", vertex, defines);
  GLuint fs = 0;
  try {
    fs = compile_stage(GL_FRAGMENT_SHADER, "GL_FRAGMENT_SHADER", fragment, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  id_ = link_program({vs, fs}, fragment);
}

Program::~Program() {
  if (id_) glDeleteProgram(id_);
}

void Program::use() const { glUseProgram(id_); }
int Program::uniform(const char* name) const { return glGetUniformLocation(id_, name); }
int Program::buffer_variable_offset(const char* name) const {
  const GLuint index = glGetProgramResourceIndex(id_, GL_BUFFER_VARIABLE, name);
  if (index == GL_INVALID_INDEX) return -1;
  const GLenum prop = GL_OFFSET;
  GLint offset = -1;
  glGetProgramResourceiv(id_, GL_BUFFER_VARIABLE, index, 1, &prop, 1, nullptr, &offset);
  return offset;
}
void Program::set(const char* name, int v) const { glProgramUniform1i(id_, uniform(name), v); }
void Program::set(const char* name, unsigned v) const { glProgramUniform1ui(id_, uniform(name), v); }
void Program::set(const char* name, float v) const { glProgramUniform1f(id_, uniform(name), v); }
void Program::set(const char* name, float x, float y, float z) const {
  glProgramUniform3f(id_, uniform(name), x, y, z);
}

void Program::set_double(const char* name, double v) const { glProgramUniform1d(id_, uniform(name), v); }
void Program::set_mat4(const char* name, const float* column_major) const {
  glProgramUniformMatrix4fv(id_, uniform(name), 1, GL_FALSE, column_major);
}

void Program::dispatch(unsigned gx, unsigned gy, unsigned gz) const {
  glUseProgram(id_);
  glDispatchCompute(gx, gy, gz);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  check_gl("glDispatchCompute");
}

Buffer::Buffer(std::size_t bytes, const void* data) : bytes_(bytes) {
  glGenBuffers(1, &id_);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glBufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(std::max<std::size_t>(bytes, 4)), data,
               GL_DYNAMIC_COPY);
  check_gl("glBufferData");
}

Buffer::~Buffer() {
  if (id_) glDeleteBuffers(1, &id_);
}

void Buffer::bind(unsigned binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

void Buffer::upload(const void* data, std::size_t bytes, std::size_t offset) {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
  check_gl("glBufferSubData");
}

void Buffer::clear() {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
  check_gl("glClearBufferData");
}

void Buffer::download(void* data, std::size_t bytes, std::size_t offset) const {
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, id_);
  glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, static_cast<GLintptr>(offset), static_cast<GLsizeiptr>(bytes), data);
  check_gl("glGetBufferSubData");
}

}  // namespace atmosh::gpu
