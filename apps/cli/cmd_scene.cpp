// atmosh scene show|check, atmosh plan, atmosh demo (the main job).
#include <chrono>
#include <iostream>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/ms.hpp"
#include "atmosh/studies/scene_run.hpp"
#include "atmosh/studies/sky_studies.hpp"
#include "atmosh/studies/studies_atmo.hpp"
#include "atmosh/studies/studies_gi.hpp"
#include "atmosh/studies/studies_prt.hpp"
#include "atmosh/studies/studies_sh.hpp"
#include "atmosh/studies/studies_sun.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
// Exactly the outputs a scene lists (and the tables they need) into dir; sky images on
// `device` (cpu | gpu | auto).
void run_scene(const scene::Scene& s, const std::filesystem::path& dir, bool quick,
               std::vector<std::filesystem::path>& written, const std::string& device = "cpu") {
  check_device(device);
  studies::SceneRunOptions o;
  o.quick = quick;
  o.device = device;
  o.notice = notice;
  o.step = [](const std::string& name, const std::function<void()>& work) { run_step(name, [&](auto&) { work(); }); };
  // Before any work: a runner for every output, and the memory the largest one holds.
  studies::check_scene_runnable(s, o);
  if (const auto m = studies::scene_peak_memory(s, o); m.bytes > 0) check_memory(m.bytes, m.what);
  check_time(studies::scene_work(s, o), 0, s.source + ": the scene");
  const auto r = studies::run_scene(s, dir, o);
  written.insert(written.end(), r.written.begin(), r.written.end());
}
}  // namespace

void register_scene_commands(CLI::App& app) {
  auto* sc = app.add_subcommand("scene", "Show or check scene files (TOML, version 1)")->require_subcommand(1);
  {
    auto* show = sc->add_subcommand("show", "Print the built-in default scene (or a file, normalised) as TOML");
    static std::string file, preset_name;
    static bool normalised = false;
    show->add_option("file", file, "Scene file to print normalised (default: the built-in scene, verbatim)");
    show->add_flag("--normalized,--normalised", normalised, "Print every setting, defaults included");
    show->add_option("--preset", preset_name, "Print a built-in atmosphere preset as a scene (earth-physical, ...)");
    show->callback([] {
      if (!preset_name.empty()) {
        scene::Scene s;
        s.atmosphere = atmo::preset(preset_name);
        std::cout << "# atmosphere preset '" << preset_name << "' in the scene schema\n" << scene::to_toml(s);
        return;
      }
      if (file.empty() && !normalised) {
        std::cout << scene::default_scene_toml();
        return;
      }
      std::cout << scene::to_toml(scene_or_default(file));
    });
  }
  {
    auto* check = sc->add_subcommand("check", "Validate a scene file; exit 2 naming the first bad key");
    static std::string file;
    check->add_option("file", file, "Scene file")->required();
    check->callback([] {
      const auto s = scene::load_scene(file);
      scene::check_outputs(s);  // what `run` needs of the scene
      std::cout << file << ": ok (" << s.outputs.size() << " output(s))\n";
    });
  }
  {
    auto* pl = app.add_subcommand("plan", "Print which passes a scene needs and which it leaves out");
    static std::string file;
    static bool json = false;
    pl->add_option("scene", file, "Scene file (default: the built-in scene)");
    add_json_flag(pl, json);
    pl->callback([] {
      const auto s = scene_or_default(file);
      scene::check_outputs(s);  // the plan of a scene that `run` refuses is refused too
      const auto passes = scene::plan(s);
      if (json) return print_json(studies::plan_json(s, passes));
      std::cout << studies::plan_text(s, passes);
    });
  }
  {
    auto* run = app.add_subcommand("run", "Compute exactly the outputs a scene lists (see `atmosh plan`)");
    static std::string file, out, device = "cpu";
    static bool quick = false;
    run->add_option("scene", file, "Scene file (default: the built-in scene)");
    run->add_option("-o,--output", out, "Output folder")->required();
    run->add_flag("--quick", quick, "Small images and coarse steps");
    add_device_option(run, device, "where the sky images are rendered");
    run->callback([] {
      const auto s = scene_or_default(file);
      std::vector<std::filesystem::path> written;
      run_scene(s, out, quick, written, device);
      for (const auto& p : scene::plan(s))
        std::cout << (p.needed ? "  ran   " : "  skip  ") << p.name << ": " << p.reason << "\n";
      print_files(written);
    });
  }
  {
    auto* demo = app.add_subcommand("demo", "Main job: run everything the toolkit does on the built-in default scene");
    static std::string out = "results";
    static bool quick = false;
    demo->add_option("-o,--output", out, "Output folder")->capture_default_str();
    demo->add_flag("--quick", quick, "Small, fast version (what the test suite runs)");
    demo->callback([] {
      const auto t0 = std::chrono::steady_clock::now();
      const std::filesystem::path dir = out;
      std::vector<std::filesystem::path> written = {dir / "scene.toml"};
      const auto s = scene::default_scene();
      io::write_text_atomically(dir / "scene.toml", std::string(scene::default_scene_toml()));
      written.push_back(studies::write_plan_csv(s, dir / "plan.csv"));
      run_scene(s, dir, quick, written);  // the scene's own outputs, then every study the toolkit has
      auto step = [&](const std::string& name, const std::function<std::vector<std::filesystem::path>()>& work) {
        run_step(name, [&](auto&) { for (const auto& f : work()) written.push_back(f); });
      };
      step("demo: sun positions", [&] {
        return studies::write_sun_accuracy(dir / "sun_accuracy", 2026, {-75.0, -45.0, 0.0, 30.0, 60.0, 85.0},
                                           quick ? 500 : 20000);
      });
      step("demo: optical depth and its tables", [&] { return studies::demo_atmo(dir); });
      step("demo: sky error against run time", [&] { return studies::demo_sky(dir, quick); });
      for (const auto& f : studies::demo_ms(dir)) written.push_back(f);
      step("demo: spherical harmonics", [&] { return studies::demo_sh(dir, quick, memory_budget() / 2); });
      step("demo: precomputed radiance transfer", [&] { return studies::demo_prt(dir / "prt", quick, notice); });
      step("demo: scene lighting (Cornell box)", [&] { return studies::demo_gi(dir / "gi", quick); });
      studies::write_manifest(dir, "atmosh demo results (" + std::string(quick ? "quick" : "full") + " run)", written);
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::cout << "atmosh demo: wrote " << written.size() << " files to " << dir.string() << "/ in " << secs << " s:\n";
      print_files(written, "  ");
      std::cout << "  (list in " << (dir / "MANIFEST.txt").string() << ")\n";
    });
  }
}

}  // namespace atmosh::cli
