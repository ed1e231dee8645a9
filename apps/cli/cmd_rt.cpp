// atmosh rt slab | rt sky — the Monte-Carlo radiative-transfer reference
// (atmosh/atmo/radiative_transfer.hpp): plane-parallel reflection and transmission
// functions, and the multiply scattered sky radiance of a scene for one view.
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "atmosh/atmo/radiative_transfer.hpp"
#include "atmosh/error.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/studies_rt.hpp"
#include "cli_common.hpp"

namespace atmosh::cli {
namespace {

using namespace atmosh::atmo;
std::int64_t require_paths(std::int64_t n, const std::string& what) {
  if (n < 1 || n > (std::int64_t{1} << 40)) throw InputError(what + " " + std::to_string(n) + ": must be in [1, 2^40]");
  return n;
}

void add_run_options(CLI::App* c, RtOptions& run, std::int64_t default_paths) {
  run.paths = default_paths;
  c->add_option("--paths", run.paths, "Monte-Carlo paths (sky: in total over the wavelengths)")->capture_default_str();
  c->add_option("--seed", run.seed, "Random seed (results are bit-identical for a seed)")->capture_default_str();
  c->add_option("--threads", run.threads, "Worker threads (0 = all cores)")->capture_default_str();
}

}  // namespace

void register_rt_commands(CLI::App& app) {
  auto* rt = app.add_subcommand(
      "rt", "Monte-Carlo radiative transfer: the exact (unbiased) multiple-scattering reference, with standard errors");
  rt->require_subcommand(1);

  // ---- rt slab ---------------------------------------------------------------
  {
    struct Opt {
      double tau = 1, omega = 1, g = 0, albedo = 0, mu0 = 1, mu = 1, phi = 0;
      std::string phase = "isotropic";
      RtOptions run;
      int orders = 0;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    auto* c = rt->add_subcommand(
        "slab",
        "Reflection and transmission functions R = pi I_up / (mu0 F0), T = pi I_down / (mu0 F0) (diffuse) of a "
        "homogeneous plane-parallel slab over a Lambertian ground");
    c->add_option("--tau", o->tau, "Optical thickness (> 0)")->required();
    c->add_option("--omega", o->omega, "Single-scattering albedo [0, 1]")->required();
    c->add_option("--phase", o->phase, "isotropic | hg | rayleigh")->required();
    c->add_option("--g", o->g, "Henyey-Greenstein asymmetry (--phase hg), (-1, 1)")->capture_default_str();
    c->add_option("--ground-albedo", o->albedo, "Lambertian ground albedo [0, 1]")->capture_default_str();
    c->add_option("--mu0", o->mu0, "Cosine of the beam's zenith angle (0, 1]")->required();
    c->add_option("--mu", o->mu, "Cosine of the viewed light's zenith angle (0, 1]")->required();
    c->add_option("--phi-deg", o->phi,
                  "Azimuth of the viewed light's propagation relative to the beam's [deg] (0: same azimuth, as "
                  "DISORT's PHI - PHI0)")
        ->capture_default_str();
    c->add_option("--orders", o->orders, "Scattering orders (0 = all)")->capture_default_str();
    add_run_options(c, o->run, 100000);
    c->add_flag("--json", o->json, "Print one JSON object");
    c->callback([o] {
      SlabSpec s;
      if (o->phase == "isotropic")
        s.phase = SlabPhase::Isotropic;
      else if (o->phase == "hg")
        s.phase = SlabPhase::HenyeyGreenstein;
      else if (o->phase == "rayleigh")
        s.phase = SlabPhase::Rayleigh;
      else
        throw InputError("--phase: '" + o->phase + "' is not isotropic, hg or rayleigh");
      s.tau = require_range(o->tau, 1e-300, 1e6, "--tau");
      if (!(s.tau > 0)) throw InputError("--tau: must be > 0");
      s.omega = require_range(o->omega, 0.0, 1.0, "--omega");
      s.g = require_range(o->g, -0.999999, 0.999999, "--g");
      s.ground_albedo = require_range(o->albedo, 0.0, 1.0, "--ground-albedo");
      const double mu0 = require_range(o->mu0, 1e-6, 1.0, "--mu0");
      const double mu = require_range(o->mu, 1e-6, 1.0, "--mu");
      const double phi = require_range(o->phi, -360.0, 360.0, "--phi-deg");
      require_paths(o->run.paths, "--paths");
      require_range(o->orders, 0, 1 << 30, "--orders");
      resolve_threads(o->run.threads, "--threads");  // the one thread-count policy
      RtOptions run = o->run;
      run.max_orders = o->orders;
      const SlabResult r = studies::rt_slab(s, mu0, mu, phi, run);
      if (o->json) {
        nlohmann::json j;
        j["tau"] = s.tau;
        j["omega"] = s.omega;
        j["phase"] = o->phase;
        j["g"] = s.g;
        j["ground_albedo"] = s.ground_albedo;
        j["mu0"] = mu0;
        j["mu"] = mu;
        j["phi_deg"] = phi;
        j["reflection"] = r.reflection;
        j["reflection_stderr"] = r.reflection_stderr;
        j["transmission"] = r.transmission;
        j["transmission_stderr"] = r.transmission_stderr;
        j["paths"] = r.paths;
        j["seed"] = run.seed;
        j["orders"] = run.max_orders;
        j["threads"] = resolve_threads(run.threads);
        j["time_s"] = r.time_s;
        print_json(j);
      } else {
        std::printf("reflection   R = %.10g +- %.3g\ntransmission T = %.10g +- %.3g\n(%lld paths each, %.3f s)\n",
                    r.reflection, r.reflection_stderr, r.transmission, r.transmission_stderr,
                    static_cast<long long>(r.paths), r.time_s);
      }
    });
  }

  // ---- rt sky ----------------------------------------------------------------
  {
    struct Opt {
      std::string scene_file;
      double sun_elevation = 30, sun_azimuth = 180, view_elevation = 90, view_azimuth = 180, height = 0;
      double ground_albedo = -1;
      std::string sun_depth = "table", line = "auto";
      RtOptions run;
      int orders = 0;
      bool json = false;
    };
    auto o = std::make_shared<Opt>();
    auto* c = rt->add_subcommand(
        "sky", "Monte-Carlo spectral radiance and luminance of a scene's sky for one view (every scattering order)");
    c->add_option("--scene", o->scene_file, "Scene file (default: built-in scene)");
    c->add_option("--sun-elevation", o->sun_elevation, "Sun elevation [deg]")->required();
    c->add_option("--sun-azimuth", o->sun_azimuth, "Sun azimuth [deg from north towards east]")->capture_default_str();
    c->add_option("--view-elevation", o->view_elevation, "View elevation [deg]")->required();
    c->add_option("--view-azimuth", o->view_azimuth, "View azimuth [deg from north towards east]")->required();
    c->add_option("--height", o->height, "Observer height above the ground [m]")->capture_default_str();
    c->add_option("--ground-albedo", o->ground_albedo, "Lambertian ground albedo (default: the scene's)");
    c->add_option("--orders", o->orders, "Scattering orders (0 = all; 1 = single scattering)")->capture_default_str();
    c->add_option("--sun-depth", o->sun_depth,
                  "table (sun optical depth from a 64 x 256 table, its error reported) | exact (quadrature per vertex, slow)")
        ->capture_default_str();
    c->add_option("--line-estimate", o->line,
                  "auto (in deep twilight, sun below -7 deg) | on | off: integrate the next vertex's sunlight along "
                  "each new direction")
        ->capture_default_str();
    add_run_options(c, o->run, 64000);
    c->add_flag("--json", o->json, "Print one JSON object");
    c->callback([o] {
      require_range(o->sun_elevation, -90.0, 90.0, "--sun-elevation");
      require_range(o->view_elevation, -90.0, 90.0, "--view-elevation");
      require_range(o->sun_azimuth, -360.0, 360.0, "--sun-azimuth");
      require_range(o->view_azimuth, -360.0, 360.0, "--view-azimuth");
      require_range(o->height, 0.0, 1e9, "--height");
      if (o->ground_albedo != -1) require_range(o->ground_albedo, 0.0, 1.0, "--ground-albedo");
      require_range(o->orders, 0, 1 << 30, "--orders");
      resolve_threads(o->run.threads, "--threads");  // the one thread-count policy
      require_paths(o->run.paths, "--paths");
      RtSkyOptions so;
      if (o->sun_depth == "table")
        so.sun_depth = RtSunDepth::Table;
      else if (o->sun_depth == "exact")
        so.sun_depth = RtSunDepth::Exact;
      else
        throw InputError("--sun-depth: '" + o->sun_depth + "' is not table or exact");
      if (o->line == "auto")
        so.line_estimate = RtLineEstimate::DeepTwilight;
      else if (o->line == "on")
        so.line_estimate = RtLineEstimate::On;
      else if (o->line == "off")
        so.line_estimate = RtLineEstimate::Off;
      else
        throw InputError("--line-estimate: '" + o->line + "' is not auto, on or off");
      const scene::Scene s = o->scene_file.empty() ? scene::default_scene() : scene::load_scene(o->scene_file);
      so.run = o->run;
      so.run.max_orders = o->orders;
      so.ground_albedo = o->ground_albedo;
      const RtSkyResult r = studies::rt_sky_view(
          s.atmosphere, {o->sun_elevation, o->sun_azimuth, o->view_elevation, o->view_azimuth, o->height}, so);
      if (o->json) {
        nlohmann::json j;
        j["scene"] = s.source;
        j["sun_elevation_deg"] = o->sun_elevation;
        j["sun_azimuth_deg"] = o->sun_azimuth;
        j["view_elevation_deg"] = o->view_elevation;
        j["view_azimuth_deg"] = o->view_azimuth;
        j["observer_height_m"] = o->height;
        j["ground_albedo"] = o->ground_albedo >= 0 ? o->ground_albedo : s.atmosphere.planet.ground_albedo;
        j["wavelengths_nm"] = r.wavelengths_nm;
        j["radiance_w_m2_sr_nm"] = r.radiance;
        j["radiance_stderr_w_m2_sr_nm"] = r.radiance_stderr;
        j["luminance_cd_m2"] = r.luminance;
        j["luminance_stderr_cd_m2"] = r.luminance_stderr;
        j["xyz"] = {r.xyz.X, r.xyz.Y, r.xyz.Z};
        j["xyz_stderr"] = {r.xyz_stderr.X, r.xyz_stderr.Y, r.xyz_stderr.Z};
        j["paths"] = r.paths;
        j["paths_per_wavelength"] = r.paths_per_wavelength;
        j["mean_orders"] = r.mean_orders;
        j["orders"] = so.run.max_orders;
        j["seed"] = so.run.seed;
        j["threads"] = resolve_threads(so.run.threads);
        j["sun_depth"] = o->sun_depth;
        j["line_estimate"] = o->line;
        j["sun_depth_rel_error"] = r.sun_depth_rel_error;
        j["time_s"] = r.time_s;
        print_json(j);
      } else {
        std::printf("luminance %.8g +- %.3g cd/m^2 (%lld paths, %.3f s)\n", r.luminance, r.luminance_stderr,
                    static_cast<long long>(r.paths), r.time_s);
        for (std::size_t i = 0; i < r.radiance.size(); ++i)
          std::printf("  %7.2f nm  %.8g +- %.3g W m^-2 sr^-1 nm^-1\n", r.wavelengths_nm[i], r.radiance[i],
                      r.radiance_stderr[i]);
      }
    });
  }
}

}  // namespace atmosh::cli
