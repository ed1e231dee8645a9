// Precomputed radiance transfer, mesh-independent part (see prt.hpp).
#include "atmosh/sh/prt.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#include "atmosh/sh/basis.hpp"
#include "atmosh/sh/convolution.hpp"
#include "atmosh/sh/fast.hpp"

namespace atmosh::sh::prt {

namespace {
constexpr double kPi = std::numbers::pi;

void check_albedo(double albedo, const char* where) {
  if (!(albedo >= 0.0 && albedo <= 1.0))
    throw InputError(std::string(where) + ": albedo must be in [0, 1], got " + std::to_string(albedo));
}

}  // namespace

TransferMode parse_transfer_mode(const std::string& name) {
  if (name == "unshadowed") return TransferMode::unshadowed;
  if (name == "shadowed") return TransferMode::shadowed;
  if (name == "interreflected") return TransferMode::interreflected;
  throw InputError("unknown transfer mode '" + name + "' (unshadowed, shadowed, interreflected)");
}

const char* transfer_mode_name(TransferMode m) {
  switch (m) {
    case TransferMode::unshadowed: return "unshadowed";
    case TransferMode::shadowed: return "shadowed";
    case TransferMode::interreflected: return "interreflected";
  }
  return "?";
}

SampleSet make_samples(int bands, const ProjectOptions& opt) {
  check_bands(bands, "prt samples", 64);
  SampleSet s;
  s.bands = bands;
  std::vector<double> w;
  sampler_directions(opt, s.dirs, w);
  s.weight = w.empty() ? 0.0 : w.front();
  const std::size_t K = static_cast<std::size_t>(s.coeffs());
  s.ylm.resize(s.dirs.size() * K);
  for (std::size_t i = 0; i < s.dirs.size(); ++i) {
    const glm::dvec3& d = s.dirs[i];
    if (bands <= kFastMaxBands)
      evaluate_fast(bands, d.x, d.y, d.z, s.ylm.data() + i * K);
    else
      evaluate(bands, d, s.ylm.data() + i * K);
  }
  return s;
}

SampleSet jittered_samples(int bands, int strata, std::uint64_t seed) {
  if (strata < 1 || strata > 20000)
    throw InputError("prt: strata per side must be in 1..20000, got " + std::to_string(strata));
  ProjectOptions opt;
  opt.method = Method::jittered;
  opt.samples = strata;
  opt.seed = seed;
  return make_samples(bands, opt);
}

void unshadowed_transfer(int bands, const glm::dvec3& normal, double albedo, double* out) {
  check_bands(bands, "unshadowed_transfer", 64);
  check_albedo(albedo, "unshadowed_transfer");
  const glm::dvec3 n = checked_direction(normal, "unshadowed_transfer normal");
  evaluate(bands, n, out);
  const std::vector<double> a = irradiance_factors(bands);  // A_l (A_0 = pi)
  for (int l = 0; l < bands; ++l)
    for (int m = -l; m <= l; ++m) out[sh_index(l, m)] *= albedo / kPi * a[l];
}

double shadowed_transfer(const SampleSet& samples, const glm::dvec3& normal, double albedo,
                         const std::function<bool(std::size_t s)>& visible, double* out) {
  check_albedo(albedo, "shadowed_transfer");
  const glm::dvec3 n = checked_direction(normal, "shadowed_transfer normal");
  const int K = samples.coeffs();
  std::fill(out, out + K, 0.0);
  double cos_sum = 0.0;
  for (std::size_t s = 0; s < samples.dirs.size(); ++s) {
    const double c = glm::dot(n, samples.dirs[s]);
    if (c <= 0.0 || !visible(s)) continue;
    cos_sum += c;
    const double* y = samples.y(s);
    for (int i = 0; i < K; ++i) out[i] += c * y[i];
  }
  const double f = albedo / kPi * samples.weight;
  for (int i = 0; i < K; ++i) out[i] *= f;
  return cos_sum * samples.weight / kPi;
}

double ambient_occlusion(double t00, double albedo) {
  if (!(albedo > 0.0 && albedo <= 1.0))
    throw InputError("ambient_occlusion: albedo must be in (0, 1], got " + std::to_string(albedo));
  return t00 * 2.0 * std::sqrt(kPi) / albedo;  // divide by rho Y_00 = rho / (2 sqrt(pi))
}

std::vector<double> interreflect(const std::vector<double>& direct, int bands, const std::vector<double>& albedo,
                                 const HitList& hits, double weight, int bounces, int threads,
                                 BounceReport* report) {
  check_bands(bands, "interreflect", 64);
  const std::size_t K = static_cast<std::size_t>(sh_count(bands));
  const std::size_t nv = albedo.size();
  if (direct.size() != nv * K || hits.size() != nv)
    throw InputError("interreflect: sizes disagree (" + std::to_string(direct.size()) + " coefficients, " +
                     std::to_string(nv) + " albedos, " + std::to_string(hits.size()) + " hit lists)");
  if (bounces < 0 || bounces > 1000) throw InputError("interreflect: bounces must be in 0..1000, got " + std::to_string(bounces));
  for (double a : albedo) check_albedo(a, "interreflect");
  if (!(weight > 0.0 && std::isfinite(weight))) throw InputError("interreflect: sample weight must be > 0");
  for (const auto& hl : hits)
    for (const Hit& h : hl)
      if (h.v[0] >= nv || h.v[1] >= nv || h.v[2] >= nv) throw InputError("interreflect: hit names a vertex out of range");

  auto energy = [&](const std::vector<double>& t) {
    double e = 0;
    for (double x : t) e += x * x;
    return e;
  };
  std::vector<double> total = direct, prev = direct, next(direct.size());
  if (report) report->energy = {energy(direct)};
  for (int b = 0; b < bounces; ++b) {
    // Blocks of 64 vertices from the toolkit's parallel loop; each vertex writes only its own row.
    atmosh::parallel_for_ranges_local(nv, 64, threads, [&] { return std::vector<double>(K); },
                                      [&](std::vector<double>& acc, std::size_t v0, std::size_t v1) {
      for (std::size_t v = v0; v < v1; ++v) {
        std::fill(acc.begin(), acc.end(), 0.0);
        for (const Hit& h : hits[v]) {
          const double w0 = 1.0 - h.b1 - h.b2, w1 = h.b1, w2 = h.b2;
          const double* t0 = prev.data() + h.v[0] * K;
          const double* t1 = prev.data() + h.v[1] * K;
          const double* t2 = prev.data() + h.v[2] * K;
          const double c = h.cos_weight;
          for (std::size_t i = 0; i < K; ++i) acc[i] += c * (w0 * t0[i] + w1 * t1[i] + w2 * t2[i]);
        }
        const double f = albedo[v] / kPi * weight;
        for (std::size_t i = 0; i < K; ++i) next[v * K + i] = f * acc[i];
      }
    });
    for (std::size_t i = 0; i < total.size(); ++i) total[i] += next[i];
    if (report) report->energy.push_back(energy(next));
    prev.swap(next);
  }
  return total;
}

double relight(const double* transfer, const double* light, int coeffs) {
  double s = 0;
  for (int i = 0; i < coeffs; ++i) s += transfer[i] * light[i];
  return s;
}

std::vector<double> directional_light(int bands, const glm::dvec3& dir, double irradiance) {
  check_bands(bands, "directional_light", 64);
  if (!std::isfinite(irradiance)) throw InputError("directional_light: irradiance is not finite");
  std::vector<double> l = evaluate(bands, checked_direction(dir, "directional_light direction"));
  for (double& x : l) x *= irradiance;
  return l;
}

}  // namespace atmosh::sh::prt
