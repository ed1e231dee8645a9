// atmosh/studies/studies_atmo.hpp — the atmosphere's studies as library calls: the
// optical-depth tables against the exact reference over a fixed set of rays (the LUT
// convergence study), optical depth against zenith angle, and the stiff-case suite's
// table. Each study takes plain inputs and returns typed rows with their provenance;
// it prints nothing and chooses no file names (the writers below take the paths).
//
// Units: SI inside (metres, radians where not stated); wavelengths in nm, angles in
// the rows in degrees as their column names say.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "atmosh/atmo/phase.hpp"
#include "atmosh/atmo/atmosphere.hpp"
#include "atmosh/atmo/spec.hpp"
#include "atmosh/atmo/stiff_cases.hpp"
#include "atmosh/io/csv.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/provenance.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/studies/study_table.hpp"

namespace atmosh::studies {

// A ray of the LUT study: radius r [m] from the planet's centre, mu = cos(zenith angle).
struct LutRay {
  double r = 0.0, mu = 0.0;
};

// The study's fixed rays: altitudes from the ground to the top (including just above
// the ground and just below the top), a uniform grid in mu plus grazing rays at
// 1e-9..3e-2 either side of the horizon and of mu = 0, rays whose tangent point lies
// 1 mm..1 km above the ground, the probe rays at the profiles' kinks
// (atmo::kink_probe_rays), and 1000 seeded random rays (seed 20261122; the same set
// on every platform). Every ray has R <= r <= R + top and -1 <= mu <= 1.
std::vector<LutRay> lut_study_rays(const atmo::Atmosphere& atm);

struct LutConvergenceOptions {
  // The settings swept: every shells x directions pair (directions per table branch,
  // view and sun alike). quick: {16 x 32, 40 x 64} only, a coarse table and the default.
  std::vector<int> shells = {16, 32, 40, 48, 64};
  std::vector<int> directions = {32, 64, 128};
  bool quick = false;
  // "cpu" (never touches EGL), "gpu" or "auto", decided by the toolkit's one device
  // policy (atmosh::resolve_device, atmosh/device.hpp): "gpu" without a usable GPU
  // throws std::runtime_error "--device gpu: <why>"; "auto" falls back to the CPU rows
  // with a notice. Only gpu::Unavailable (no device) and gpu::Unsupported (an
  // atmosphere the table pass does not take) fall back; other errors propagate. With a GPU every setting gets a
  // second row, lut_gpu: the tables built by the GPU table pass, looked up on the CPU.
  std::string device = "cpu";
  // One-line notices (the GPU fallback of "auto"); empty: none.
  std::function<void(const std::string&)> notice;
};

// Optical-depth tables (atmo::OpticalDepthLut) against the exact reference
// (atmo::OpticalDepthReference) at 550 nm over lut_study_rays(): the first row is the
// reference itself (its own quadrature error estimate), then one row `lut` per
// setting, `lut_plain` where the tables subtract kinks of a tabulated profile (the
// same tables without), `lut_gpu` as above. Columns as in docs/atmosphere.md: error
// of the total optical depth (max, rms), time = build + lookups of all rays, shells,
// directions, rays, build_time_s, lookup_time_ns, table_bytes, flag_mismatches
// (hits-ground flags that disagree with the reference), error_max_rel_rayleigh_mie,
// error_estimate_rel (OpticalDepthLut::estimate_max_rel_error), subtracted_kinks.
StudyTable lut_convergence(const atmo::AtmosphereSpec& spec, const LutConvergenceOptions& options);

// Optical depth at 550 nm against zenith angle 0..180 deg in 0.5 deg steps, from
// `altitude_m` above the ground: the reference and the default tables.
struct ZenithRow {
  double zenith_deg = 0.0;
  double tau_reference = 0.0, tau_lut = 0.0;
  double relative_error = 0.0;  // |tau_lut - tau_reference| / tau_reference (0 where the reference is 0)
  bool hits_ground = false;
};
struct ZenithSweep {
  std::vector<ZenithRow> rows;
  std::string lut_name;  // "LUT <shells>x<directions>"
  io::Provenance provenance;
};
ZenithSweep zenith_sweep(const atmo::AtmosphereSpec& spec, double altitude_m);
// Its table (STEM.csv): zenith_deg, tau_reference, tau_lut, relative_error,
// hits_ground (0/1). The one place its columns are made (CSV, the Python DataFrame).
io::CsvTable zenith_sweep_table(const ZenithSweep& sweep);
// STEM.csv and STEM.png (the reference as a line, every 4th table value as points).
std::vector<std::filesystem::path> write_zenith_sweep(const ZenithSweep& sweep, const std::string& atmosphere_name,
                                                      double altitude_m, const std::filesystem::path& stem);

// Optical depth along one ray at the atmosphere's first wavelength, from altitude_m
// above the ground (>= 0) at zenith_deg (90 = horizontal, > 90 looks down), by the
// exact reference (its own quadrature error estimate) or by tables of the given size
// (error estimate: OpticalDepthLut::estimate_max_rel_error times the total, computed
// after the clock stops). time_s: the reference's integral, or table build + lookup.
struct OpticalDepthQuery {
  double altitude_m = 0.0, zenith_deg = 0.0;
  bool tables = false;  // false: reference; true: atmo::OpticalDepthLut
  int shells = 40, directions = 64;
};
struct OpticalDepthAnswer {
  double rayleigh = 0.0, mie = 0.0, ozone = 0.0, total = 0.0;
  double error_estimate = 0.0;  // absolute, of the total
  double time_s = 0.0;
  bool hits_ground = false;
};
OpticalDepthAnswer optical_depth_query(const atmo::Atmosphere& atmosphere, const OpticalDepthQuery& query);

// `atmosh optical-depth`: the query at one wavelength of an atmosphere, checked first
// (InputError naming --wavelength 1..1e5 nm and inside the ozone table and the physical
// Rayleigh model's range where the atmosphere has them, --zenith 0..180 deg, --altitude
// 0..1e9 m).
OpticalDepthAnswer optical_depth_at(atmo::AtmosphereSpec spec, double wavelength_nm, const OpticalDepthQuery& query);

// `atmosh phase`: the phase function of a model as the command line names it
// (rayleigh | hg | cornette-shanks | double-hg) with its parameters. g has no default
// (required for the Henyey-Greenstein models); a parameter the model does not take is an
// error when given (*_given). InputError naming --model, --g, --g2, --weight or
// --depolarization.
struct PhaseRequest {
  std::string model;
  double g = 0.8, g2 = -0.3, weight = 0.9, depolarization = 0.0279;
  bool g_given = false, g2_given = false, weight_given = false, depolarization_given = false;
};
atmo::PhaseSpec phase_spec(const PhaseRequest& request);

// The stiff/extreme-case table (atmo::run_stiff_cases) as CSV with provenance.
void write_stability_csv(const std::vector<atmo::StiffCase>& cases, const std::filesystem::path& file);

// The atmosphere step of the main job (`atmosh demo`) into `dir`: optical depth against
// zenith angle 1 km above the default scene's ground (optical_depth_vs_zenith.csv/.png)
// and the stiff-case table (stability.csv); std::runtime_error if a case fails its bound.
// Returns the files in order.
std::vector<std::filesystem::path> demo_atmo(const std::filesystem::path& dir);

}  // namespace atmosh::studies
