// Precomputed radiance transfer's studies and drivers (atmosh/studies/studies_prt.hpp).
#include "atmosh/studies/studies_prt.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <tuple>

#include <glm/geometric.hpp>

#include "atmosh/device.hpp"
#include "atmosh/error.hpp"
#include "atmosh/parallel.hpp"
#ifdef ATMOSH_HAVE_GPU
#include "atmosh/gpu/context.hpp"
#include "atmosh/gpu/sky.hpp"  // gpu::Unsupported
#endif
#include "atmosh/io/exr.hpp"
#include "atmosh/io/output_check.hpp"
#include "atmosh/io/plot.hpp"
#include "atmosh/io/rgb_image.hpp"
#include "atmosh/io/study.hpp"
#include "atmosh/studies/summaries.hpp"
#include "atmosh/check.hpp"

namespace atmosh::studies {

namespace fs = std::filesystem;

namespace {
constexpr double kPi = std::numbers::pi;
using Clock = std::chrono::steady_clock;

// Writes STEM.exr, STEM.png (tone-mapped) and STEM.png.json (the tone mapping, as for
// sky images).
std::vector<fs::path> write_image(const fs::path& stem, const std::vector<std::vector<float>>& img, int w, int h,
                                  double exposure, const std::string& exposure_rule, const io::Provenance& prov,
                                  const std::string& what) {
  io::ExrImage ex(w, h, {"R", "G", "B"});
  for (int c = 0; c < 3; ++c) ex.data[c] = img[std::min<std::size_t>(c, img.size() - 1)];
  ex.string_attributes["atmosh:quantity"] = what;
  ex.string_attributes["atmosh:units"] = "units of the light (exit radiance = transfer . light)";
  const fs::path exr = stem.string() + ".exr", png = stem.string() + ".png";
  return io::write_rgb_image(exr, ex, png, exposure, exposure_rule, prov);
}

// Writes the frames of `lights` rendered by `render(light)` and returns the files.
template <class Render>
std::vector<fs::path> write_frames(const std::vector<ShLight>& lights, const Render& render,
                                   const RelightImageOptions& o, int w, int h, const io::Provenance& prov,
                                   const fs::path& dir) {
  std::vector<fs::path> written;
  double exposure = o.exposure;
  for (std::size_t f = 0; f < lights.size(); ++f) {
    const std::vector<std::vector<float>> img = render(lights[f]);
    if (exposure <= 0) exposure = auto_exposure(img[0]);  // fixed by the first frame
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu", f);
    const std::string rule = o.exposure > 0 ? o.given_exposure_rule
                                            : "1 / (99th percentile of the first channel of frame 0), every frame";
    auto wr = write_image(dir / name, img, w, h, exposure, rule, prov, "relit exit radiance");
    written.insert(written.end(), wr.begin(), wr.end());
  }
  return written;
}
}  // namespace

std::vector<ShLight> turning_lights(const std::vector<glm::dvec3>& directions, int frames, int bands) {
  if (frames < 1) throw InputError("frames: must be >= 1, got " + std::to_string(frames));
  std::vector<ShLight> lights;
  for (const glm::dvec3& dir : directions) {
    if (glm::length(dir) == 0) throw InputError("light direction: zero vector");
    for (int f = 0; f < frames; ++f) {  // the light turned about +z in `frames` steps
      const double a = 2 * kPi * f / frames;
      const glm::dvec3 r(std::cos(a) * dir.x - std::sin(a) * dir.y, std::sin(a) * dir.x + std::cos(a) * dir.y, dir.z);
      lights.push_back({sh::prt::directional_light(bands, r, kPi)});  // E = pi: white Lambertian -> rho V cos
    }
  }
  return lights;
}

double auto_exposure(std::vector<float> v) { return io::percentile_exposure(std::move(v)); }

std::vector<fs::path> relight_vertices_to(const prt::Transfer& t, const std::vector<ShLight>& lights,
                                          const RelightImageOptions& o, const fs::path& dir) {
  if (glm::length(o.view) == 0) throw InputError("view direction: zero vector");
  std::vector<fs::path> written;
  const prt::RayScene scene(t.mesh);
  auto prov = io::Provenance::current();
  prov.add("transfer_bands", std::to_string(t.bands)).add("transfer_mode", sh::prt::transfer_mode_name(t.mode));
  // Simple occlusion: band 0 scaled to ambient occlusion.
  {
    std::vector<std::vector<double>> ao(t.mesh.positions.size(), std::vector<double>(1));
    for (std::size_t v = 0; v < ao.size(); ++v)
      ao[v][0] = t.mesh.albedo[v] > 0 ? sh::prt::ambient_occlusion(t.at(v)[0], t.mesh.albedo[v]) : t.ao[v];
    const auto img = prt::render_vertex_values(scene, t.mesh, ao, o.width, o.height, o.view);
    auto w = write_image(dir / "ao", img, o.width, o.height, 1.0, "1 (occlusion is in [0, 1])", prov,
                         "ambient occlusion from SH band 0");
    written.insert(written.end(), w.begin(), w.end());
  }
  auto render = [&](const ShLight& light) {
    return prt::render_vertex_values(scene, t.mesh, prt::relight_vertices(t, light), o.width, o.height, o.view);
  };
  const auto frames = write_frames(lights, render, o, o.width, o.height, prov, dir);
  written.insert(written.end(), frames.begin(), frames.end());
  return written;
}

std::vector<fs::path> relight_pixels_to(const io::TransferImage& ex, const std::string& source,
                                        const std::vector<ShLight>& lights, const RelightImageOptions& o,
                                        const fs::path& dir) {
  const std::size_t np = static_cast<std::size_t>(ex.width) * ex.height;
  auto prov = io::Provenance::current();
  prov.add("transfer_bands", std::to_string(ex.bands)).add("transfer_file", source);
  std::vector<fs::path> written = write_image(dir / "ao", {ex.ao}, ex.width, ex.height, 1.0, "1 (occlusion is in [0, 1])",
                                             prov, "ambient occlusion (cosine-weighted visible fraction)");
  auto render = [&](const ShLight& light) {
    std::vector<std::vector<float>> img(light.size(), std::vector<float>(np, 0.0f));
    for (std::size_t c = 0; c < light.size(); ++c)
      for (std::size_t p = 0; p < np; ++p) {
        double v = 0;
        for (std::size_t i = 0; i < ex.coefficients.size(); ++i) v += ex.coefficients[i][p] * light[c][i];
        img[c][p] = static_cast<float>(v);
      }
    return img;
  };
  const auto frames = write_frames(lights, render, o, ex.width, ex.height, prov, dir);
  written.insert(written.end(), frames.begin(), frames.end());
  return written;
}

io::TransferImage transfer_image(const prt::PixelTransfer& px, sh::prt::TransferMode mode, const std::string& view) {
  const bool gpu_run = px.device == prt::Device::gpu;
  const std::size_t K = static_cast<std::size_t>(px.bands) * px.bands, np = px.mask.size();
  io::TransferImage ex;
  ex.width = px.width;
  ex.height = px.height;
  ex.bands = px.bands;
  ex.coefficients.assign(K, std::vector<float>(np));
  for (std::size_t i = 0; i < K; ++i)
    for (std::size_t p = 0; p < np; ++p) ex.coefficients[i][p] = static_cast<float>(px.coeffs[p * K + i]);
  ex.ao.resize(np);
  for (std::size_t p = 0; p < np; ++p) ex.ao[p] = static_cast<float>(px.ao[p]);
  ex.mask = px.mask;
  ex.attributes["quantity"] = std::string("per-pixel diffuse transfer, ") + sh::prt::transfer_mode_name(mode);
  ex.attributes["view"] = view;
  ex.attributes["samples"] = std::to_string(px.samples);
  ex.attributes["device"] = gpu_run ? "gpu" : "cpu";
  if (gpu_run) ex.attributes["depth_map"] = std::to_string(px.depth_resolution);
  return ex;
}

std::pair<double, double> transfer_error(const prt::Transfer& t, const prt::Transfer& ref) {
  const std::size_t nv = ref.mesh.positions.size(), K = static_cast<std::size_t>(ref.bands) * ref.bands;
  double scale = 0, emax = 0, esum = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    double s = 0;
    for (std::size_t i = 0; i < K; ++i) s += ref.at(v)[i] * ref.at(v)[i];
    scale = std::max(scale, std::sqrt(s));
  }
  for (std::size_t v = 0; v < nv; ++v) {
    double e = 0;
    for (std::size_t i = 0; i < K; ++i) e += std::pow(t.at(v)[i] - ref.at(v)[i], 2);
    emax = std::max(emax, std::sqrt(e));
    esum += e;
  }
  scale = scale > 0 ? scale : 1.0;
  return {emax / scale, std::sqrt(esum / static_cast<double>(nv)) / scale};
}

std::pair<double, double> pixel_error(const prt::PixelTransfer& t, const prt::PixelTransfer& ref) {
  const std::size_t np = ref.mask.size(), K = static_cast<std::size_t>(ref.bands) * ref.bands;
  double scale = 0, emax = 0, esum = 0, n = 0;
  for (std::size_t p = 0; p < np; ++p) {
    double s = 0;
    for (std::size_t i = 0; i < K; ++i) s += ref.coeffs[p * K + i] * ref.coeffs[p * K + i];
    scale = std::max(scale, std::sqrt(s));
  }
  for (std::size_t p = 0; p < np; ++p) {
    if (t.mask[p] == 0 || ref.mask[p] == 0) continue;
    double e = 0;
    for (std::size_t i = 0; i < K; ++i) e += std::pow(t.coeffs[p * K + i] - ref.coeffs[p * K + i], 2);
    emax = std::max(emax, std::sqrt(e));
    esum += e;
    n += 1;
  }
  scale = scale > 0 ? scale : 1.0;
  return {emax / scale, n > 0 ? std::sqrt(esum / n) / scale : 0.0};
}

StudyTable prt_convergence(const prt::Mesh& mesh, const PrtConvergenceOptions& px) {
  const int bands = px.bands, ref_strata = px.reference_strata;
  const sh::prt::TransferMode mode = px.mode;
  const std::vector<int>& strata = px.strata;
  const DeviceRequest request = parse_device_request(px.device, "device");
  prt::BakeOptions bo;
  bo.bands = bands;
  bo.mode = mode;
  bo.threads = px.threads;
  bo.strata = ref_strata;
  bo.seed = 12345;  // the reference uses its own seed: independent of the rows
  const prt::Transfer ref = prt::bake(mesh, bo);
  StudyTable out;
  std::vector<io::StudyRow>& rows = out.rows;
  bo.strata = 1;
  prt::bake(mesh, bo);  // warm-up: one-time library start-up is not part of any row's time
  const std::string mode_name = sh::prt::transfer_mode_name(mode);
  for (int s : strata) {
    bo.strata = s;
    bo.seed = 1;
    const auto t0 = Clock::now();
    const prt::Transfer t = prt::bake(mesh, bo);
    const double dt = std::chrono::duration<double>(Clock::now() - t0).count();
    const auto [emax, erms] = transfer_error(t, ref);
    rows.push_back({"cpu-" + mode_name + "-jittered", std::to_string(s * s) + " samples", emax, erms, dt,
                    {static_cast<double>(s * s), static_cast<double>(t.rays), 0.0}});
  }
  io::Provenance& prov = out.provenance;
  prov = io::Provenance::current();
  // Per-pixel rows (shadowed only): CPU ray casting and the GPU depth-map method against
  // a per-pixel reference of the same camera.
  std::string gpu_note = px.cpu_only_note;
  if (mode == sh::prt::TransferMode::shadowed) {
    bo.strata = ref_strata;
    bo.seed = 12345;
    bo.device = prt::Device::cpu;
    const prt::PixelTransfer pref = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
    // The one device policy (atmosh::resolve_device): "gpu" runs the depth-map rows or
    // fails; "auto" drops them with a notice. Only "no device" (gpu::Unavailable) and
    // "input not supported" (gpu::Unsupported) fall back: a shader or input error of
    // the warm-up is reported, not hidden behind the CPU rows.
    bool gpu = request != DeviceRequest::cpu;
    if (gpu) {
      std::optional<GpuUnusable> unusable;
#ifdef ATMOSH_HAVE_GPU
      bo.device = prt::Device::gpu;
      bo.strata = 1;
      bo.depth_resolution = px.depth_maps.front();
      try {
        prt::bake_pixels(mesh, bo, px.width, px.height, px.view);  // warm-up (driver start-up, shader compile)
        gpu_note = "depth-map method, per pixel";
      } catch (const gpu::Unavailable& e) {
        unusable = GpuUnusable{GpuUnusable::Why::no_device, e.what(), {}};
        gpu_note = std::string("not run (") + e.what() + ")";
      } catch (const gpu::Unsupported& e) {
        unusable = GpuUnusable{GpuUnusable::Why::unsupported, e.what(), {}};
        gpu_note = std::string("not run (") + e.what() + " is not supported on the GPU)";
      }
#else
      unusable = GpuUnusable{GpuUnusable::Why::not_built, {}, {}};
      gpu_note = "not run (built without GPU support)";
#endif
      if (unusable) {
        const DeviceDecision d = resolve_device(request, unusable, "the study has no GPU rows");
        if (px.notice && !d.notice.empty()) px.notice(d.notice);
        gpu = false;
      }
    }
    std::vector<std::vector<io::StudyRow>> gpu_rows(px.depth_maps.size());  // one line per depth map
    for (int s : strata) {
      bo.strata = s;
      bo.seed = 1;
      bo.device = prt::Device::cpu;
      auto t0 = Clock::now();
      const prt::PixelTransfer c = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
      double dt = std::chrono::duration<double>(Clock::now() - t0).count();
      auto [emax, erms] = pixel_error(c, pref);
      rows.push_back({"cpu-pixel-" + mode_name + "-jittered", std::to_string(s * s) + " samples", emax, erms, dt,
                      {static_cast<double>(s * s), static_cast<double>(c.rays), 0.0}});
      if (!gpu) continue;
      bo.device = prt::Device::gpu;
      for (std::size_t k = 0; k < px.depth_maps.size(); ++k) {
        const int d = px.depth_maps[k];
        bo.depth_resolution = d;
        t0 = Clock::now();
        const prt::PixelTransfer g = prt::bake_pixels(mesh, bo, px.width, px.height, px.view);
        dt = std::chrono::duration<double>(Clock::now() - t0).count();
        std::tie(emax, erms) = pixel_error(g, pref);
        gpu_rows[k].push_back({"gpu-depthmap" + std::to_string(d) + "-" + mode_name + "-jittered",
                               std::to_string(s * s) + " samples", emax, erms, dt,
                               {static_cast<double>(s * s), 0.0, static_cast<double>(d)}});
      }
    }
    for (const auto& g : gpu_rows) rows.insert(rows.end(), g.begin(), g.end());
    prov.add("pixel_image", std::to_string(px.width) + "x" + std::to_string(px.height));
    prov.add("pixel_error_definition",
             "per pixel seen by both: |T - T_ref|_2 / max_p |T_ref|_2, reference: CPU ray casting, same camera");
  } else {
    gpu_note = "not run (per-pixel rows are shadowed only)";
  }
  io::StudySpec& spec = out.spec;
  spec.title = "PRT transfer (" + mesh.name + ", " + std::to_string(bands) + " bands) vs " +
               std::to_string(ref_strata * ref_strata) + "-sample reference";
  spec.extra_columns = {"samples", "rays", "depth_map"};
  prov.add("mesh", mesh.name).add("bands", std::to_string(bands)).add("mode", mode_name);
  prov.add("reference_samples", std::to_string(ref_strata * ref_strata));
  prov.add("error_definition", "per-vertex rows: per-vertex |T - T_ref|_2 / max_v |T_ref|_2");
  prov.add("gpu_method", gpu_note);
  return out;
}

std::vector<fs::path> demo_prt(const fs::path& dir, bool quick, const std::function<void(const std::string&)>& notice) {
  std::vector<fs::path> written;
  prt::BakeOptions bo;
  bo.bands = quick ? 3 : 4;
  bo.strata = quick ? 12 : 45;
  bo.mode = sh::prt::TransferMode::interreflected;
  bo.bounces = 2;
  const prt::Mesh mesh = prt::builtin_scene("sphere-on-plane", quick ? 12 : 40);
  const prt::Transfer t = prt::bake(mesh, bo);
  auto prov = io::Provenance::current();
  prov.add("mesh", mesh.name);
  const fs::path tf = dir / "sphere_on_plane_transfer.ply";
  prt::write_transfer(tf, t, prov);
  written.push_back(tf);
  RelightImageOptions image;
  image.width = image.height = quick ? 96 : 384;
  const auto lights = turning_lights({glm::dvec3(1.0, 0.3, 1.2)}, quick ? 2 : 12, t.bands);
  for (const auto& f : relight_vertices_to(t, lights, image, dir / "relight")) written.push_back(f);
  PrtConvergenceOptions c;  // GPU rows where an EGL device exists (llvmpipe included)
  c.bands = 3;
  c.mode = sh::prt::TransferMode::shadowed;
  c.reference_strata = quick ? 24 : 128;
  c.strata = quick ? std::vector<int>{3, 6} : std::vector<int>{4, 8, 16, 32, 45};
  c.threads = 0;
  c.width = c.height = quick ? 32 : 96;
  c.device = "auto";
  c.depth_maps = quick ? std::vector<int>{64, 256} : std::vector<int>{256, 1024};
  c.notice = notice;
  const StudyTable st = prt_convergence(prt::builtin_scene("sphere-on-plane", quick ? 6 : 16), c);
  for (const auto& f : io::write_study(dir / "converge", st.spec, st.rows, st.provenance)) written.push_back(f);
  return written;
}

prt::Mesh prt_input_mesh(const std::string& mesh_file, const std::string& builtin, int resolution) {
  if (!mesh_file.empty() && !builtin.empty()) throw InputError("give either MESH or --scene-builtin, not both");
  if (mesh_file.empty() && builtin.empty()) throw InputError("no mesh: give MESH (.obj, .ply) or --scene-builtin NAME");
  return builtin.empty() ? prt::load_mesh(mesh_file) : prt::builtin_scene(builtin, resolution);
}

int strata_of_samples(int n, const std::string& option) {
  const int s = static_cast<int>(std::lround(std::sqrt(static_cast<double>(std::max(n, 0)))));
  if (n < 1 || s * s != n || s > 2000)
    throw InputError(option + ": " + std::to_string(n) +
                     " is not a square count of jittered strata n x n in 1..4000000 (e.g. 2025 = 45 x 45)");
  return s;
}

prt::BakeOptions prt_bake_options(const PrtBakeRequest& o) {
  prt::BakeOptions bo;
  if (o.device != "cpu" && o.device != "gpu") throw InputError("--device: unknown device '" + o.device + "' (cpu, gpu)");
  bo.device = prt::parse_device(o.device);
  if (o.bounces < 0 || o.bounces > 100) throw InputError("--bounces: must be in 0..100, got " + std::to_string(o.bounces));
  if (!(o.albedo >= 0 && o.albedo <= 1)) throw InputError("--albedo: must be in [0, 1], got " + std::to_string(o.albedo));
  bo.depth_resolution = o.depth_map;
  if (o.depth_map < 16 || o.depth_map > 16384)
    throw InputError("--depth-map: must be in 16..16384, got " + std::to_string(o.depth_map));
  bo.mode = sh::prt::parse_transfer_mode(o.mode);
  bo.bands = o.bands;
  if (o.bands < 1 || o.bands > 16) throw InputError("--bands: must be in 1..16, got " + std::to_string(o.bands));
  bo.strata = strata_of_samples(o.samples);
  bo.bounces = o.bounces;
  bo.default_albedo = o.albedo;
  bo.seed = o.seed;
  bo.threads = resolve_threads(o.threads, "--threads");
  const std::string ext = fs::path(o.output).extension().string();
  if (ext != ".ply" && ext != ".exr")
    throw InputError("-o: '" + o.output + "' must end in .ply (per-vertex) or .exr (per-pixel)");
  io::check_output_file(o.output, {".ply", ".exr"}, "-o");
  if (bo.device == prt::Device::gpu && ext != ".exr")
    throw InputError("--device gpu: the depth-map method is per-pixel; write an .exr (per-vertex bakes use --device cpu)");
  if (ext == ".exr" && bo.mode == sh::prt::TransferMode::interreflected)
    throw InputError("--mode interreflected: per-pixel transfer is unshadowed or shadowed");
  return bo;
}

nlohmann::json prt_bake_to(const prt::Mesh& mesh, const prt::BakeOptions& bo, const std::string& file,
                           std::array<int, 2> size, const std::string& view) {
  const auto vv = parse_triple(view, "--view");
  auto prov = [&] { return io::Provenance::current().add("mesh", mesh.name); };
  const auto t0 = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  if (fs::path(file).extension() == ".exr") {  // per-pixel transfer: CPU ray casting or the GPU depth-map method
    const prt::PixelTransfer px = prt::bake_pixels(mesh, bo, size[0], size[1], {vv[0], vv[1], vv[2]});
    const double dt = seconds();
    io::write_transfer_exr(file, transfer_image(px, bo.mode, view), prov());
    return prt_pixel_bake_json(px, bo.mode, file, dt);
  }
  const prt::Transfer t = prt::bake(mesh, bo);
  const double dt = seconds();
  prt::write_transfer(file, t, prov());
  return prt_bake_json(t, file, dt);
}

}  // namespace atmosh::studies
