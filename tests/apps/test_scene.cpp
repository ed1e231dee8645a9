// Scene files: the built-in scene, strict validation with key paths, TOML round trip, plan.
#include <gtest/gtest.h>

#include <algorithm>

#include "atmosh/atmo/presets.hpp"
#include "atmosh/error.hpp"
#include "atmosh/scene/scene.hpp"

using namespace atmosh::scene;

namespace {
// Expects parse failure whose message names `key`.
void expect_bad(const std::string& toml, const std::string& key) {
  try {
    parse_scene(toml, "t.toml");
    ADD_FAILURE() << "accepted:\n" << toml;
  } catch (const atmosh::InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(key), std::string::npos) << "message '" << msg << "' does not name " << key;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    EXPECT_EQ(msg.rfind("t.toml", 0), 0u) << msg;
  }
}
const Pass& find(const std::vector<Pass>& ps, const std::string& name) {
  auto it = std::find_if(ps.begin(), ps.end(), [&](const Pass& p) { return p.name == name; });
  if (it == ps.end()) throw std::runtime_error("no pass " + name);
  return *it;
}
}  // namespace

TEST(Scene, DefaultSceneParsesWithAllConstituents) {
  const Scene s = default_scene();
  ASSERT_TRUE(s.atmosphere.rayleigh && s.atmosphere.mie && s.atmosphere.ozone);
  EXPECT_DOUBLE_EQ(s.atmosphere.planet.radius_m, 6360e3);
  EXPECT_DOUBLE_EQ(s.atmosphere.mie->profile.scale_height_m, 1200.0);
  EXPECT_EQ(s.atmosphere.mie->phase.model, atmosh::atmo::PhaseSpec::Model::CornetteShanks);
  ASSERT_TRUE(s.observer.has_value());
  EXPECT_DOUBLE_EQ(s.observer->latitude_deg, 48.8566);
  EXPECT_EQ(s.atmosphere.spectrum.count, 16);
  EXPECT_FALSE(s.outputs.empty());
}

TEST(Scene, TomlRoundTripIsExact) {
  const Scene a = default_scene();
  const Scene b = parse_scene(to_toml(a), "roundtrip.toml");
  EXPECT_EQ(to_toml(a), to_toml(b));
  EXPECT_EQ(b.atmosphere.mie->scattering_per_m, a.atmosphere.mie->scattering_per_m);
  EXPECT_EQ(b.atmosphere.ozone->profile.peak_m, a.atmosphere.ozone->profile.peak_m);
}

TEST(Scene, OmittedTablesLeaveConstituentsOut) {
  const Scene s = parse_scene("version = 1\n[rayleigh]\nscale_height_m = 8000\n[sun]\nelevation_deg = 5\n"
                              "[[output]]\nkind = \"sky-image\"\nfile = \"a.exr\"\n",
                              "t.toml");
  EXPECT_TRUE(s.atmosphere.rayleigh.has_value());
  EXPECT_FALSE(s.atmosphere.mie.has_value());
  EXPECT_FALSE(s.atmosphere.ozone.has_value());
  const auto ps = plan(s);
  EXPECT_TRUE(find(ps, "constituent:rayleigh").needed);
  EXPECT_TRUE(find(ps, "optical-depth-lut:sun").needed);
  EXPECT_FALSE(find(ps, "optical-depth-lut:view").needed);  // view depths accumulated along each ray
  EXPECT_FALSE(find(ps, "constituent:mie").needed);
  EXPECT_NE(find(ps, "constituent:mie").reason.find("[mie]"), std::string::npos);
  EXPECT_FALSE(find(ps, "constituent:ozone").needed);
  EXPECT_FALSE(find(ps, "sun-position").needed);  // [sun] gives the direction directly
  EXPECT_TRUE(find(ps, "sky-radiance:single-scattering").needed);
  EXPECT_FALSE(find(ps, "sh-projection").needed);
}

TEST(Scene, PlanWithoutSkyOutputsSkipsTables) {
  const Scene s = parse_scene("version = 1\n[rayleigh]\n[observer]\ntime_utc = \"2026-06-21T12:00:00Z\"\n"
                              "[[output]]\nkind = \"sun-track\"\nfile = \"t.csv\"\n", "t.toml");
  const auto ps = plan(s);
  EXPECT_FALSE(find(ps, "optical-depth-lut:view").needed);
  EXPECT_FALSE(find(ps, "optical-depth-lut:sun").needed);
  EXPECT_FALSE(find(ps, "constituent:rayleigh").needed);
  EXPECT_FALSE(find(ps, "sh-projection").needed);
  // SH coefficients are those of the sky: they need it (and its tables).
  const Scene sh = parse_scene(
      "version = 1\n[rayleigh]\n[sun]\n[[output]]\nkind = \"sh-coefficients\"\nbands = 5\nfile = \"c.csv\"\n", "t.toml");
  const auto pss = plan(sh);
  EXPECT_FALSE(find(pss, "optical-depth-lut:view").needed);
  EXPECT_TRUE(find(pss, "constituent:rayleigh").needed);
  EXPECT_TRUE(find(pss, "sh-projection").needed);
  EXPECT_NE(find(pss, "sh-projection").reason.find("25 coefficients"), std::string::npos);
}

// [observer] is an atmo::Observer plus a time, validated with its range (observer.hpp):
// the Dead Sea shore (about -430 m) is accepted, below -500 m is refused naming the key.
TEST(Scene, ObserverIsTheLibrarysObserver) {
  const Scene s = parse_scene("version = 1\n[observer]\nlatitude_deg = 31.5\nlongitude_deg = 35.5\nheight_m = -430\n"
                              "time_utc = \"2026-01-01T00:00:00Z\"\n",
                              "t.toml");
  ASSERT_TRUE(s.observer);
  const atmosh::atmo::Observer& place = *s.observer;
  EXPECT_NO_THROW(atmosh::atmo::validate_observer(place));
  EXPECT_EQ(place.height_m, -430.0);
  expect_bad("version = 1\n[observer]\nheight_m = -501\ntime_utc = \"2026-01-01T00:00:00Z\"", "observer.height_m");
  expect_bad("version = 1\n[observer]\nheight_m = 2e8\ntime_utc = \"2026-01-01T00:00:00Z\"", "observer.height_m");
}

TEST(Scene, ValidationNamesTheKey) {
  expect_bad("", "version");
  expect_bad("version = 2", "version");
  expect_bad("version = 1\nfoo = 3", "foo");
  expect_bad("version = 1\n[mie]\nscale_heigth_m = 3", "mie.scale_heigth_m");
  expect_bad("version = 1\n[mie]\nscale_height_m = \"tall\"", "mie.scale_height_m");
  expect_bad("version = 1\n[mie]\nscale_height_m = nan", "mie.scale_height_m");
  expect_bad("version = 1\n[mie]\nphase = { model = \"lorentz\" }", "mie.phase.model");
  expect_bad("version = 1\n[ozone]\nprofile = { model = \"tent\", bottom = 3 }", "ozone.profile.bottom");
  expect_bad("version = 1\n[observer]\nlatitude_deg = 91\ntime_utc = \"2026-01-01T00:00:00Z\"", "observer.latitude_deg");
  expect_bad("version = 1\n[observer]\nlatitude_deg = 10", "observer.time_utc");
  expect_bad("version = 1\n[sun]\nazimuth_deg = 360", "sun.azimuth_deg");
  expect_bad("version = 1\n[spectrum]\ncount = 0", "spectrum.count");
  expect_bad("version = 1\n[[output]]\nkind = \"hologram\"\nfile = \"x\"", "output[0].kind");
  expect_bad("version = 1\n[[output]]\nkind = \"sky-image\"\nfile = \"x\"\nsize = [0, 3]", "output[0].size");
  expect_bad("version = 1\n[[output]]\nkind = \"sky-image\"", "output[0].file");
  expect_bad("version = 1\n[observer]\ntime_utc = \"2026-01-01T00:00:00Z\"\n[sun]\nelevation_deg = 3", "sun");
  expect_bad("version = 1\n[mie\n", "TOML syntax error");
  expect_bad("version = 1\n[scattering]\nmethod = \"double\"", "scattering.method");
  expect_bad("version = 1\n[scattering]\norders = 0", "scattering.orders");
  expect_bad("version = 1\n[scattering]\norders_view_directions = 9", "scattering.orders_view_directions");
  expect_bad("version = 1\n[scattering]\nms_ray_steps = 1", "scattering.ms_ray_steps");
  expect_bad("version = 1\n[scattering]\nordres = 3", "scattering.ordres");
}

// [scattering]: the default scene uses multiple scattering, a scene without the table
// keeps single scattering, the plan lists the extra tables only when they are built,
// and the table survives the TOML round trip.
TEST(Scene, ScatteringMethodPlanAndRoundTrip) {
  const Scene d = default_scene();
  EXPECT_EQ(d.scattering.method, atmosh::atmo::ScatteringMethod::Approximate);
  EXPECT_TRUE(find(plan(d), "multiple-scattering:approximate-table").needed);
  EXPECT_FALSE(find(plan(d), "multiple-scattering:orders-tables").needed);
  Scene single = parse_scene("version = 1\n[rayleigh]\n[sun]\nelevation_deg = 10\n[[output]]\nkind = \"sky-image\"\nfile = \"s.exr\"\n",
                             "s.toml");
  EXPECT_EQ(single.scattering.method, atmosh::atmo::ScatteringMethod::Single);
  EXPECT_FALSE(find(plan(single), "multiple-scattering:approximate-table").needed);
  EXPECT_FALSE(find(plan(single), "multiple-scattering:orders-tables").needed);
  const Scene orders = parse_scene(
      "version = 1\n[rayleigh]\n[sun]\nelevation_deg = 10\n[scattering]\nmethod = \"orders\"\norders = 5\norders_radii = 8\n"
      "[[output]]\nkind = \"sky-image\"\nfile = \"s.exr\"\n",
      "o.toml");
  EXPECT_EQ(orders.scattering.orders, 5);
  const std::vector<Pass> po = plan(orders);
  const Pass& p = find(po, "multiple-scattering:orders-tables");
  EXPECT_TRUE(p.needed);
  EXPECT_NE(p.reason.find("orders 2..5"), std::string::npos) << p.reason;
  const Scene back = parse_scene(to_toml(orders), "back.toml");
  EXPECT_EQ(back.scattering.method, atmosh::atmo::ScatteringMethod::Orders);
  EXPECT_EQ(back.scattering.orders, 5);
  EXPECT_EQ(back.scattering.orders_radii, 8);
  EXPECT_EQ(to_toml(back), to_toml(orders));
}

TEST(Scene, PhysicalRangesNamedByKey) {
  expect_bad("version = 1\n[mie]\nscale_height_m = -5", "mie.profile");
  expect_bad("version = 1\n[planet]\natmosphere_top_m = -1", "planet.atmosphere_top_m");
  expect_bad("version = 1\n[planet]\nradius_m = 0", "planet.radius_m");
  expect_bad("version = 1\n[rayleigh]\npressure_pa = -3", "rayleigh.pressure_pa");
  // Finite but extreme: the number density p / (k T) or the tables' sizes would
  // overflow (they gave null optical depths with exit 0, or a failure with exit 1).
  expect_bad("version = 1\n[rayleigh]\npressure_pa = 1e300", "rayleigh.pressure_pa");
  expect_bad("version = 1\n[rayleigh]\ntemperature_k = 1e-300", "rayleigh.temperature_k");
  expect_bad("version = 1\n[planet]\nradius_m = 1e300\natmosphere_top_m = 1e300", "planet.radius_m");
  expect_bad("version = 1\n[planet]\natmosphere_top_m = 1e300", "planet.atmosphere_top_m");
  expect_bad("version = 1\n[mie]\nphase = { model = \"hg\", g = 1.5 }", "mie.phase.g");
  expect_bad("version = 1\n[ozone]\ncolumn_du = -300", "ozone.column_du");
  expect_bad("version = 1\n[spectrum]\nfrom_nm = 500\nto_nm = 400", "spectrum.to_nm");
}

// The U.S. 1976 generator as a profile model: the same table as earth-physical's
// Rayleigh profile at the defaults, finer with step_m; out-of-range values named.
TEST(Scene, UsStandard1976ProfileModel) {
  const Scene a = parse_scene("version = 1\n[rayleigh]\nprofile = { model = \"us-standard-1976\" }\n", "t.toml");
  const auto& p = a.atmosphere.rayleigh->profile;
  const auto want = atmosh::atmo::preset("earth-physical").rayleigh->profile;
  EXPECT_EQ(p.altitude_m, want.altitude_m);
  EXPECT_EQ(p.value, want.value);
  const Scene b =
      parse_scene("version = 1\n[rayleigh]\nprofile = { model = \"us-standard-1976\", step_m = 100 }\n", "t.toml");
  const auto& f = b.atmosphere.rayleigh->profile;
  EXPECT_EQ(f.altitude_m.size(), 1006u);  // 1001 grid nodes and the 5 boundaries not within 10 m of one
  EXPECT_EQ(f.value, atmosh::atmo::us_standard_1976_profile(100e3, 100.0).value);
  expect_bad("version = 1\n[rayleigh]\nprofile = { model = \"us-standard-1976\", step_m = 1 }", "rayleigh.profile.step_m");
  expect_bad("version = 1\n[rayleigh]\nprofile = { model = \"us-standard-1976\", top_m = -5 }", "rayleigh.profile.top_m");
  expect_bad("version = 1\n[rayleigh]\nprofile = { model = \"us-standard-1976\", scale = 2 }", "rayleigh.profile.scale");
}

// Presets and scene files share one schema: every preset written as TOML reads back
// to the same TOML (and so to the same parameters).
TEST(Scene, PresetsRoundTripThroughTheSceneSchema) {
  for (const auto& name : atmosh::atmo::preset_names()) {
    Scene s;
    s.atmosphere = atmosh::atmo::preset(name);
    const std::string t = to_toml(s);
    const Scene back = parse_scene(t, name + ".toml");
    EXPECT_EQ(to_toml(back), t) << name;
    EXPECT_EQ(back.atmosphere.rayleigh.has_value(), s.atmosphere.rayleigh.has_value()) << name;
    EXPECT_EQ(back.atmosphere.spectrum.wavelengths_nm, s.atmosphere.spectrum.wavelengths_nm) << name;
  }
}
