// The scene runner (see atmosh/studies/scene_run.hpp).
#include "atmosh/studies/scene_run.hpp"

#include <algorithm>

#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "atmosh/studies/studies_sun.hpp"

namespace atmosh::studies {

namespace fs = std::filesystem;

const SunPlacement& SceneRunContext::sun() {
  if (!sun_) {
    sun_ = sun_of_scene(scene);
    spa_computed = sun_->spa.has_value();
  }
  return *sun_;
}

const SkyModel& SceneRunContext::sky() {
  if (!model_) {
    const SunPlacement& s = sun();
    // Orders tables on the device of the scene's sky images (the one policy:
    // use_orders_tables_device; the sky-image runner renders on options.device), kept
    // there: the images bind them, and an output that looks them up on the CPU at the
    // scene's observer (sh-coefficients) reads back that part only.
    scene::Scene sc = scene;
    const std::string where = use_orders_tables_device(sc, options.device, options.notice, true);
    model_ = make_sky_model(sc, SkySettings{}.sky(sc), s.distance_au);
    model_->orders_tables_device = where;
    ++skies_built;
  }
  return *model_;
}

std::array<int, 2> SceneRunContext::image_size(const scene::Output& out) const {
  const bool q = options.quick;
  return {q ? std::min(64, out.size[0]) : out.size[0], q ? std::min(32, out.size[1]) : out.size[1]};
}

// ---- one runner per kind of scene::output_kinds() (add a kind: one entry here) ----
const std::map<std::string_view, OutputRunner>& scene_output_runners() {
  static const std::map<std::string_view, OutputRunner> runners = {
      {"sky-image",
       [](SceneRunContext& ctx, const scene::Output& out, const fs::path& file, const fs::path&) {
         const SkyModel& m = ctx.sky();
         const SunPlacement& sun = ctx.sun();
         const auto [w, h] = ctx.image_size(out);
         std::string used;
         const auto img = render_sky_on(ctx.options.device, *m.sky, atmo::parse_sky_projection(out.projection), w, h,
                                        std::max(sun.observer_height_m, 0.0), sun.direction(), out.spectral, 0, used,
                                        ctx.options.notice);
         fs::path png = file;
         png.replace_extension(".png");
         auto prov = sky_provenance(m, sun);
         prov.add("device", used);
         write_sky_image(img, file, png, prov, out.projection, sun);
         fs::path side = png;
         side += ".json";  // the tone mapping (write_sky_image)
         return std::vector<fs::path>{file, png, side};
       }},
      {"sh-coefficients",
       [](SceneRunContext& ctx, const scene::Output& out, const fs::path& file, const fs::path&) {
         const SkyModel& m = ctx.sky();
         read_back_orders_at(m, std::max(ctx.sun().observer_height_m, 0.0), ctx.sun().direction());
         const auto* k = scene::find_output_kind(out.kind);
         return write_sky_sh(project_sky_sh(m, ctx.sun(), out.bands > 0 ? out.bands : k->default_bands), file);
       }},
      {"sun-track",
       [](SceneRunContext& ctx, const scene::Output&, const fs::path&, const fs::path& stem) {
         const auto& ob = *ctx.scene.observer;  // check_outputs: a sun-track has an [observer]
         ctx.spa_computed = true;                // its suns are NREL SPA's
         return write_sun_day_track(
             sun_day_track(ob.latitude_deg, ob.longitude_deg, ob.height_m, ob.time_utc, ctx.options.quick ? 1800.0 : 600.0),
             ob.latitude_deg, ob.longitude_deg, stem);
       }},
      {"lut-convergence",
       [](SceneRunContext& ctx, const scene::Output&, const fs::path&, const fs::path& stem) {
         LutConvergenceOptions o;  // the default settings (CPU), or the quick pair
         o.quick = ctx.options.quick;
         const StudyTable t = lut_convergence(ctx.scene.atmosphere, o);
         return io::write_study(stem, t.spec, t.rows, t.provenance);
       }},
      {"optical-depth",
       [](SceneRunContext& ctx, const scene::Output&, const fs::path&, const fs::path& stem) {
         constexpr double kAltitude = 1000.0;  // m above the ground
         return write_zenith_sweep(zenith_sweep(ctx.scene.atmosphere, kAltitude), ctx.scene.atmosphere.name, kAltitude,
                                   stem);
       }},
      {"sun-elevation-study",
       [](SceneRunContext& ctx, const scene::Output&, const fs::path&, const fs::path& stem) {
         // The study runs on all the CPUs this process may use, as `study sun-elevation`
         // does; that count goes into the provenance of every file written after it.
         io::set_threads(resolve_threads(0));
         ElevationStudyOptions e;
         e.step_deg = ctx.options.quick ? 12 : 1;
         e.sky.device = ctx.options.device;  // its orders tables: the sky images' device policy
         e.sky.notice = ctx.options.notice;
         const ElevationStudy st = sun_elevation_study(ctx.scene, e);  // its own suns and sky
         ++ctx.skies_built;
         return write_elevation_study(st, stem);
       }},
  };
  return runners;
}

namespace {
const OutputRunner* runner_of(const SceneRunOptions& o, std::string_view kind) {
  if (auto it = o.runners.find(kind); it != o.runners.end()) return &it->second;
  const auto& lib = scene_output_runners();
  if (auto it = lib.find(kind); it != lib.end()) return &it->second;
  return nullptr;
}
}  // namespace

void check_scene_runnable(const scene::Scene& s, const SceneRunOptions& o) {
  check_device_name(o.device);
  scene::check_outputs(s);  // what each kind needs (the scene reader checked it too)
  for (const auto& out : s.outputs)
    if (runner_of(o, out.kind) == nullptr) throw InputError(s.source + ": output kind '" + out.kind + "' has no runner");
}

SceneMemory scene_peak_memory(const scene::Scene& s, const SceneRunOptions& o) {
  SceneRunContext ctx(s, o);
  SceneMemory m;
  for (const auto& out : s.outputs) {
    const std::size_t bytes = scene_output_bytes(s, out, ctx.image_size(out));
    if (bytes > m.bytes) m.bytes = bytes, m.what = s.source + ": output '" + out.file + "' (" + out.kind + ")";
  }
  return m;
}

WorkEstimate scene_work(const scene::Scene& s, const SceneRunOptions& o) {
  SceneRunContext ctx(s, o);
  WorkEstimate w;
  for (const auto& out : s.outputs) w = w + scene_output_work(s, out, ctx.image_size(out), o.quick);
  return w;
}

SceneRun run_scene(const scene::Scene& s, const fs::path& dir, const SceneRunOptions& o) {
  check_scene_runnable(s, o);
  SceneRunContext ctx(s, o);
  SceneRun r;
  for (std::size_t oi = 0; oi < s.outputs.size(); ++oi) {
    const auto& out = s.outputs[oi];
    const fs::path file = dir / out.file;
    fs::path stem = file;
    stem.replace_extension();
    auto work = [&] {
      for (const auto& f : (*runner_of(o, out.kind))(ctx, out, file, stem)) r.written.push_back(f);
    };
    if (o.step)
      o.step("output[" + std::to_string(oi) + "] " + out.kind + " " + out.file, work);
    else
      work();
  }
  r.skies_built = ctx.skies_built;
  r.spa_computed = ctx.spa_computed;
  return r;
}

fs::path write_plan_csv(const scene::Scene& s, const fs::path& csv) {
  io::CsvTable t({"pass", "needed", "reason"});
  for (const auto& p : scene::plan(s)) t.add_row({p.name, std::int64_t{p.needed ? 1 : 0}, p.reason});
  auto prov = io::Provenance::current();
  prov.add("scene", s.source);
  t.write(csv, prov);
  return csv;
}

fs::path write_manifest(const fs::path& dir, const std::string& title, const std::vector<fs::path>& files) {
  std::string text = "# " + title + "\n";
  for (const auto& f : files) text += f.lexically_relative(dir).string() + "\n";
  io::write_text_atomically(dir / "MANIFEST.txt", text);
  return dir / "MANIFEST.txt";
}

}  // namespace atmosh::studies
