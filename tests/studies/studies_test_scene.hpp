// A small scene for the studies' tests: the toolkit's atmosphere with four
// wavelengths and single scattering, so each study runs in well under a second.
#pragma once

#include <string>

#include "atmosh/scene/scene.hpp"
#include "atmosh/studies/sky.hpp"

namespace atmosh::test {

inline std::string small_scene_toml(const std::string& sun_or_observer) {
  return "version = 1\n[rayleigh]\n[mie]\n[ozone]\n[spectrum]\nfrom_nm = 400.0\nto_nm = 700.0\ncount = 4\n"
         "[scattering]\nmethod = \"single\"\n" +
         sun_or_observer;
}
inline scene::Scene small_scene(const std::string& sun_or_observer = "[sun]\nelevation_deg = 20.0\nazimuth_deg = 150.0\n") {
  return scene::parse_scene(small_scene_toml(sun_or_observer), "small.toml");
}
inline const char* kParisObserver =
    "[observer]\nlatitude_deg = 48.8566\nlongitude_deg = 2.3522\nheight_m = 35.0\ntime_utc = \"2026-06-21T18:30:00Z\"\n";

// Coarse tables: the studies' bookkeeping is under test, not the integrator's accuracy.
inline studies::SkySettings coarse_settings() {
  studies::SkySettings k;
  k.shells = 16;
  k.segments = 8;
  k.samples = 2;
  k.threads = 2;
  return k;
}

}  // namespace atmosh::test
