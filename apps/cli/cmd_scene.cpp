// atmosh scene show|check, atmosh plan, atmosh demo (the main job).
#include <chrono>
#include <iostream>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/atomic.hpp"
#include "atmosh/scene/outputs.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/studies/scene_run.hpp"
#include "atmosh/studies/studies_gi.hpp"
#include "cli_common.hpp"
#include "progress.hpp"

namespace atmosh::cli {

namespace {
scene::Scene scene_from(const std::string& file) {
  return file.empty() ? scene::default_scene() : scene::load_scene(file);
}
}  // namespace

void run_scene(const scene::Scene& s, const std::filesystem::path& dir, bool quick,
               std::vector<std::filesystem::path>& written, const std::string& device) {
  check_device(device);
  studies::SceneRunOptions o;
  o.quick = quick;
  o.device = device;
  o.notice = [](const std::string& m) { std::cerr << "atmosh: " << m << "\n"; };
  o.step = [](const std::string& name, const std::function<void()>& work) {
    ProgressStep step(name);
    work();
  };
  // Before any work: a runner for every output, and the memory the largest one holds.
  studies::check_scene_runnable(s, o);
  if (const auto m = studies::scene_peak_memory(s, o); m.bytes > 0) check_memory(m.bytes, m.what);
  check_time(studies::scene_work(s, o), 0, s.source + ": the scene");
  const auto r = studies::run_scene(s, dir, o);
  written.insert(written.end(), r.written.begin(), r.written.end());
}

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
      std::cout << scene::to_toml(scene_from(file));
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
    pl->add_flag("--json", json, "Print one JSON object");
    pl->callback([] {
      const auto s = scene_from(file);
      scene::check_outputs(s);  // the plan of a scene that `run` refuses is refused too
      const auto passes = scene::plan(s);
      const auto mem = studies::scene_peak_memory(s, {});  // the estimates `run` checks against its budgets
      const auto work = studies::scene_work(s, {});
      if (json) {
        nlohmann::json j;
        j["scene"] = s.source;
        j["passes"] = nlohmann::json::array();
        for (const auto& p : passes) j["passes"].push_back({{"pass", p.name}, {"needed", p.needed}, {"reason", p.reason}});
        j["estimate"] = {{"peak_memory_bytes", mem.bytes}, {"cpu_seconds", work.cpu_seconds()},
                         {"workers", available_cpus()}, {"wall_seconds", work.wall_seconds(available_cpus())},
                         {"units", work.units}, {"unit", work.unit}, {"seconds_per_unit", work.seconds_per_unit}};
        print_json(j);
        return;
      }
      std::cout << "plan for " << s.source << "\n";
      for (const auto& p : passes)
        std::cout << (p.needed ? "  run   " : "  skip  ") << p.name << std::string(p.name.size() < 34 ? 34 - p.name.size() : 1, ' ')
                  << p.reason << "\n";
      std::cout << "  estimate: memory "
                << (mem.bytes > 0 ? format_bytes(static_cast<double>(mem.bytes)) + " at most (" + mem.what + ")" : "small")
                << ", computing " << (work.units > 0 ? describe_work(work, 0) : "small") << "\n";
    });
  }
  {
    auto* run = app.add_subcommand("run", "Compute exactly the outputs a scene lists (see `atmosh plan`)");
    static std::string file, out, device = "cpu";
    static bool quick = false;
    run->add_option("scene", file, "Scene file (default: the built-in scene)");
    run->add_option("-o,--output", out, "Output folder")->required();
    run->add_flag("--quick", quick, "Small images and coarse steps");
    run->add_option("--device", device, "sky images on cpu, gpu or auto (GPU if a headless EGL device exists)")
        ->capture_default_str();
    run->callback([] {
      const auto s = scene_from(file);
      std::vector<std::filesystem::path> written;
      run_scene(s, out, quick, written, device);
      for (const auto& p : scene::plan(s))
        std::cout << (p.needed ? "  ran   " : "  skip  ") << p.name << ": " << p.reason << "\n";
      for (const auto& f : written) std::cout << f.string() << "\n";
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
      DemoContext ctx;
      ctx.out_dir = out;
      ctx.quick = quick;
      const auto s = scene::default_scene();
      io::write_text_atomically(ctx.out_dir / "scene.toml", std::string(scene::default_scene_toml()));
      ctx.written.push_back(ctx.out_dir / "scene.toml");
      ctx.written.push_back(studies::write_plan_csv(s, ctx.out_dir / "plan.csv"));
      run_scene(s, ctx.out_dir, ctx.quick, ctx.written);  // the scene's own outputs
      demo_sun(ctx);                                     // then every study the toolkit has
      demo_atmo(ctx);
      demo_sky(ctx);
      demo_ms(ctx);
      demo_sh(ctx);
      demo_prt(ctx);
      {
        ProgressStep step("demo: scene lighting (Cornell box)");
        for (const auto& f : studies::demo_gi(ctx.out_dir / "gi", ctx.quick)) ctx.written.push_back(f);
      }
      studies::write_manifest(ctx.out_dir, "atmosh demo results (" + std::string(quick ? "quick" : "full") + " run)",
                              ctx.written);
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::cout << "atmosh demo: wrote " << ctx.written.size() << " files to " << ctx.out_dir.string() << "/ in "
                << secs << " s:\n";
      for (const auto& f : ctx.written) std::cout << "  " << f.string() << "\n";
      std::cout << "  (list in " << (ctx.out_dir / "MANIFEST.txt").string() << ")\n";
    });
  }
}

}  // namespace atmosh::cli
