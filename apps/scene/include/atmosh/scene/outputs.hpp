// atmosh/scene/outputs.hpp — the one table of scene output kinds.
//
// Each kind says what it needs: the single-scattering sky (atmosphere, sun-ray
// optical-depth table, spectrum), a sun position ([observer] or [sun]), a place and
// time ([observer]), the atmosphere's spectral quantities, SH bands, and whether it
// may run on the GPU; and which files it writes. The scene reader (kinds, keys and
// requirements: `scene check`), the pass plan (`plan`) and the runner (`run`, which
// holds one function per kind and refuses a scene whose kind has none before any
// work) all read this table.
//
// Adding an output kind: one entry in output_kinds() (apps/scene/src/outputs.cpp),
// and its runner under the same name in studies::scene_output_runners()
// (apps/studies/src/studies_scene.cpp). `scene check`, `plan`, the memory check and
// `run` follow from the entry; Studies.EveryOutputKindHasOneRunner and
// Studies.PlanAndRunAgreeOnEveryKind hold the runner to it.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "atmosh/scene/scene.hpp"

namespace atmosh::scene {

struct OutputKind {
  std::string_view name;
  std::string_view summary;
  bool sky = false;         // the single-scattering sky of the scene's atmosphere
  bool sun = false;         // a sun position: [observer] (place and time) or [sun]
  bool observer = false;    // a place and time: [observer]
  bool atmosphere = false;  // the atmosphere (constituents, spectrum) without the sky
  bool bands = false;       // reads `bands` (SH bands, default default_bands)
  bool image = false;       // reads `size`, `projection`, `spectral`
  bool gpu = false;         // computed on --device gpu when asked
  int default_bands = 0;
  // A pass of its own that `plan` lists (needed when the scene has this kind), or empty.
  std::string_view plan_pass;
  // Files written, relative to the output folder: "{file}" is the output's file,
  // "{stem}" the file without its extension; a trailing '/' is a folder.
  std::vector<std::string_view> files;
};

// Every kind, in a fixed order.
const std::vector<OutputKind>& output_kinds();
// The kind of that name, or nullptr.
const OutputKind* find_output_kind(std::string_view name);
// "a, b, c": the kinds' names, for messages.
std::string output_kind_names();
// The files an output writes (relative to the output folder), from its kind's patterns.
std::vector<std::string> output_files(const Output& output);
// Checks the scene against what its outputs need (a sun, an [observer]); throws
// InputError "<source>: output[i] (<kind>): ..." naming the first output that cannot
// run. `scene check`, `plan` and `run` (run_scene) call it, so they refuse alike.
void check_outputs(const Scene& scene);

}  // namespace atmosh::scene
