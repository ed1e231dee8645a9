// atmosh/studies/scene_run.hpp — computing exactly the outputs a scene lists.
//
// The table of output kinds (what each needs, the files it writes) is
// atmosh/scene/outputs.hpp; the runner of each kind is in scene_output_runners()
// (apps/studies/src/studies_scene.cpp). Adding an output kind: one entry in
// output_kinds() (apps/scene/src/outputs.cpp) and its runner in the table of
// studies_scene.cpp; the test Studies.EveryOutputKindHasOneRunner holds the two
// tables to each other.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky.hpp"

namespace atmosh::studies {

struct SceneRunOptions;

// What a runner gets: the scene, the options, and the sky and sun built once for all
// outputs that need them (on first use).
class SceneRunContext {
 public:
  SceneRunContext(const scene::Scene& s, const SceneRunOptions& o) : scene(s), options(o) {}
  const scene::Scene& scene;
  const SceneRunOptions& options;
  const SkyModel& sky();       // the scene's sky (default settings), built once
  const SunPlacement& sun();   // the scene's sun (sun_of_scene), placed once
  // Image size of an output: its own, or at most 64 x 32 for a quick run.
  std::array<int, 2> image_size(const scene::Output& out) const;
  int skies_built = 0;         // sky integrators built for this run
  bool spa_computed = false;   // the sun was placed by NREL SPA ([observer])

 private:
  std::optional<SunPlacement> sun_;
  std::unique_ptr<SkyModel> model_;
};

// Computes one output: `file` is dir/out.file, `stem` the same without its extension.
// Returns the files written.
using OutputRunner = std::function<std::vector<std::filesystem::path>(
    SceneRunContext&, const scene::Output&, const std::filesystem::path& file, const std::filesystem::path& stem)>;

struct SceneRunOptions {
  bool quick = false;           // small images and coarse steps
  std::string device = "cpu";   // sky images on cpu | gpu | auto (render_sky_on)
  Notice notice;                // one-line fallback notices (device)
  // Runs the work of one output (the CLI wraps it in a progress display); empty: runs it.
  std::function<void(const std::string& step, const std::function<void()>& work)> step;
  // Runners of kinds computed outside this library (by name); they take precedence.
  std::map<std::string, OutputRunner, std::less<>> runners;
};

// The runners of this library, by kind (see the top of this header).
const std::map<std::string_view, OutputRunner>& scene_output_runners();

// Before any work: the kinds' requirements (scene::check_outputs), a device name, and a
// runner for every output; InputError "<source>: output kind '<k>' has no runner".
void check_scene_runnable(const scene::Scene& s, const SceneRunOptions& o);

// The largest memory one output holds (bytes) and which output it is ("" when 0).
struct SceneMemory {
  std::size_t bytes = 0;
  std::string what;
};
SceneMemory scene_peak_memory(const scene::Scene& s, const SceneRunOptions& o);
// The work of all its outputs (atmosh/work.hpp; studies::scene_output_work), one after
// the other.
WorkEstimate scene_work(const scene::Scene& s, const SceneRunOptions& o);

struct SceneRun {
  std::vector<std::filesystem::path> written;
  int skies_built = 0;        // sky integrators built
  bool spa_computed = false;  // sun from [observer] by NREL SPA
};
// Computes exactly the outputs a scene lists into dir (check_scene_runnable first).
SceneRun run_scene(const scene::Scene& s, const std::filesystem::path& dir, const SceneRunOptions& o);

// The scene's plan (scene::plan) as CSV: pass, needed (0/1), reason; the scene in its
// provenance. Returns the file.
std::filesystem::path write_plan_csv(const scene::Scene& s, const std::filesystem::path& csv);
// A manifest: one title line "# <title>", then each file relative to dir, one a line.
std::filesystem::path write_manifest(const std::filesystem::path& dir, const std::string& title,
                                     const std::vector<std::filesystem::path>& files);

}  // namespace atmosh::studies
