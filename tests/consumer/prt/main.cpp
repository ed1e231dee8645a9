// Downstream use of the installed atmosh::prt: bakes transfer on a small built-in mesh
// and checks the white-furnace property. Under a uniform distant light of radiance L
// (SH coefficients l_0 = 2 sqrt(pi) L, all others 0) a Lambertian surface of albedo rho
// with nothing occluding it leaves radiance rho L (Sloan, Kautz & Snyder 2002, eq. of the
// diffuse transfer with V = 1; the clamped-cosine integral over the hemisphere is pi).
// The lone sphere is convex, so the shadowed bake (Embree rays) must agree to its Monte
// Carlo error (below 1e-2 of rho L at 2025 samples, docs/prt.md) and the unshadowed bake
// (closed form) to rounding. Exit 0 on success.
#include <atmosh/error.hpp>
#include <atmosh/prt/bake.hpp>
#include <atmosh/prt/mesh.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

int main() {
  const double pi = std::acos(-1.0), rho = 0.8, radiance = 3.0;
  const atmosh::prt::Mesh mesh = atmosh::prt::builtin_scene("sphere", 8);
  atmosh::prt::BakeOptions opt;
  opt.bands = 2;
  opt.strata = 45;
  opt.threads = 1;
  opt.default_albedo = rho;
  std::vector<double> light(4, 0.0);
  light[0] = 2.0 * std::sqrt(pi) * radiance;
  double worst[2] = {0, 0};
  int k = 0;
  for (auto mode : {atmosh::sh::prt::TransferMode::unshadowed, atmosh::sh::prt::TransferMode::shadowed}) {
    opt.mode = mode;
    const auto transfer = atmosh::prt::bake(mesh, opt);
    for (const auto& out : atmosh::prt::relight_vertices(transfer, {light}))
      worst[k] = std::fmax(worst[k], std::fabs(out[0] - rho * radiance) / (rho * radiance));
    ++k;
  }
  std::printf("%zu vertices; white furnace, worst relative error: unshadowed %.3g, shadowed %.3g\n",
              mesh.vertex_count(), worst[0], worst[1]);
  return worst[0] < 1e-12 && worst[1] < 1e-2 ? 0 : 1;
}
