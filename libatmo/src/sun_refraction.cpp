// sun_refraction.cpp — see sun_refraction.hpp for the model and its sources.
#include "atmosh/atmo/sun_refraction.hpp"

#include <cmath>
#include <string>

#include "atmosh/error.hpp"

namespace atmosh::atmo {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

// SPA eq. 42 without the pressure/temperature factor, in degrees, and its
// derivative with respect to h (deg/deg). Valid for h > -5.11 + tiny.
double spa_refraction_unit(double h) { return 1.02 / (60.0 * std::tan((h + 10.3 / (h + 5.11)) * kDeg)); }

double spa_refraction_unit_slope(double h) {
  const double x = (h + 10.3 / (h + 5.11)) * kDeg;
  const double s = std::sin(x);
  const double dxdh = 1.0 - 10.3 / ((h + 5.11) * (h + 5.11));
  return -1.02 / 60.0 / (s * s) * dxdh * kDeg;
}

}  // namespace

double refraction_deg(double h, double pressure_hpa, double temperature_c) {
  if (!std::isfinite(h) || !std::isfinite(pressure_hpa) || !std::isfinite(temperature_c))
    throw InputError("refraction: non-finite elevation, pressure or temperature");
  if (temperature_c <= -273.0)
    throw InputError("temperature " + std::to_string(temperature_c) + " C is at or below absolute zero");
  if (pressure_hpa <= 0.0) return 0.0;
  if (h > 90.0) h = 90.0;
  if (h < -90.0) h = -90.0;
  const double scale = (pressure_hpa / 1010.0) * (283.0 / (273.0 + temperature_c));
  if (h >= kRefractionBlendDeg) return scale * spa_refraction_unit(h);
  const double rb = spa_refraction_unit(kRefractionBlendDeg);
  const double sb = spa_refraction_unit_slope(kRefractionBlendDeg);
  const double d = h - kRefractionBlendDeg;
  const double g = d / kRefractionTailWidthDeg;
  return scale * (rb + sb * d) * std::exp(-g * g);
}

double apparent_elevation_deg(double h, double pressure_hpa, double temperature_c) {
  return h + refraction_deg(h, pressure_hpa, temperature_c);
}

}  // namespace atmosh::atmo
