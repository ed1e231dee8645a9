// atmosh rt slab | rt sky — the Monte-Carlo radiative-transfer reference
// (atmosh/atmo/radiative_transfer.hpp): plane-parallel reflection and transmission
// functions, and the multiply scattered sky radiance of a scene for one view.
#include <cstdio>
#include <memory>

#include "atmosh/studies/studies_rt.hpp"
#include "atmosh/studies/summaries.hpp"
#include "cli_common.hpp"

namespace atmosh::cli {
namespace {

void add_run_options(CLI::App* c, atmo::RtOptions& run, std::int64_t default_paths) {
  run.paths = default_paths;
  c->add_option("--paths", run.paths, "Monte-Carlo paths (sky: in total over the wavelengths)")->capture_default_str();
  c->add_option("--seed", run.seed, "Random seed (results are bit-identical for a seed)")->capture_default_str();
  add_threads_option(c, run.threads);
}

}  // namespace

void register_rt_commands(CLI::App& app) {
  auto* rt = app.add_subcommand(
      "rt", "Monte-Carlo radiative transfer: the exact (unbiased) multiple-scattering reference, with standard errors");
  rt->require_subcommand(1);
  {
    static studies::RtSlabRequest o;
    static bool json = false;
    auto* c = rt->add_subcommand(
        "slab",
        "Reflection and transmission functions R = pi I_up / (mu0 F0), T = pi I_down / (mu0 F0) (diffuse) of a "
        "homogeneous plane-parallel slab over a Lambertian ground");
    c->add_option("--tau", o.tau, "Optical thickness (> 0)")->required();
    c->add_option("--omega", o.omega, "Single-scattering albedo [0, 1]")->required();
    c->add_option("--phase", o.phase, "isotropic | hg | rayleigh")->required();
    c->add_option("--g", o.g, "Henyey-Greenstein asymmetry (--phase hg), (-1, 1)")->capture_default_str();
    c->add_option("--ground-albedo", o.ground_albedo, "Lambertian ground albedo [0, 1]")->capture_default_str();
    c->add_option("--mu0", o.mu0, "Cosine of the beam's zenith angle (0, 1]")->required();
    c->add_option("--mu", o.mu, "Cosine of the viewed light's zenith angle (0, 1]")->required();
    c->add_option("--phi-deg", o.phi_deg,
                  "Azimuth of the viewed light's propagation relative to the beam's [deg] (0: same azimuth, as "
                  "DISORT's PHI - PHI0)")
        ->capture_default_str();
    c->add_option("--orders", o.orders, "Scattering orders (0 = all)")->capture_default_str();
    add_run_options(c, o.run, 100000);
    add_json_flag(c, json);
    c->callback([] {
      const atmo::SlabResult r = studies::rt_slab(o);
      if (json) return print_json(studies::rt_slab_json(o, r));
      std::fputs(studies::rt_slab_text(r).c_str(), stdout);
    });
  }
  {
    static studies::RtSkyRequest o;
    static std::string scene_file;
    static bool json = false;
    auto* c = rt->add_subcommand(
        "sky", "Monte-Carlo spectral radiance and luminance of a scene's sky for one view (every scattering order)");
    add_scene_option(c, scene_file);
    c->add_option("--sun-elevation", o.view.sun_elevation_deg, "Sun elevation [deg]")->required();
    c->add_option("--sun-azimuth", o.view.sun_azimuth_deg, "Sun azimuth [deg from north towards east]")->capture_default_str();
    c->add_option("--view-elevation", o.view.view_elevation_deg, "View elevation [deg]")->required();
    c->add_option("--view-azimuth", o.view.view_azimuth_deg, "View azimuth [deg from north towards east]")->required();
    c->add_option("--height", o.view.observer_height_m, "Observer height above the ground [m]")->capture_default_str();
    c->add_option("--ground-albedo", o.ground_albedo, "Lambertian ground albedo (default: the scene's)");
    c->add_option("--orders", o.orders, "Scattering orders (0 = all; 1 = single scattering)")->capture_default_str();
    c->add_option("--sun-depth", o.sun_depth,
                  "table (sun optical depth from a 64 x 256 table, its error reported) | exact (quadrature per vertex, slow)")
        ->capture_default_str();
    c->add_option("--line-estimate", o.line_estimate,
                  "auto (in deep twilight, sun below -7 deg) | on | off: integrate the next vertex's sunlight along "
                  "each new direction")
        ->capture_default_str();
    c->add_option("--guide", o.guide,
                  "auto (sun below -5 deg) | on | off: draw scattering directions partly from a pilot estimate of "
                  "where the sunlit air is (docs/radiative-transfer.md)")
        ->capture_default_str();
    add_run_options(c, o.run, 64000);
    add_json_flag(c, json);
    c->callback([] {
      const scene::Scene s = scene_or_default(scene_file);
      const atmo::RtSkyResult r = studies::rt_sky_view(s.atmosphere, o);
      if (json) return print_json(studies::rt_sky_json(o, s, r));
      std::fputs(studies::rt_sky_text(r).c_str(), stdout);
    });
  }
}

}  // namespace atmosh::cli
