// embedded_sources.hpp (private to atmosh::gpu) — the table of GLSL sources that the
// build generates (cmake/AtmoshEmbedGlsl.cmake); program.cpp serves it through
// embedded_source() and embedded_source_paths().
#pragma once

namespace atmosh::gpu::detail {

struct EmbeddedSource {
  const char* path;
  int first_line;
  const char* text;
};
extern const EmbeddedSource kEmbeddedSources[];
extern const int kEmbeddedSourceCount;

}  // namespace atmosh::gpu::detail
