// The one linear-RGB image writer (atmosh/io/rgb_image.hpp).
#include "atmosh/io/rgb_image.hpp"

#include <algorithm>

#include "atmosh/io/plot.hpp"

namespace atmosh::io {

double percentile_exposure(std::vector<float> v) {
  std::sort(v.begin(), v.end());
  const double p = v.empty() ? 1.0 : v[static_cast<std::size_t>(0.99 * (v.size() - 1))];
  return p > 0 ? 1.0 / p : 1.0;
}

std::vector<std::filesystem::path> write_rgb_image(const std::filesystem::path& exr, const ExrImage& ex,
                                                   const std::filesystem::path& png, double exposure,
                                                   const std::string& exposure_rule, const Provenance& prov) {
  write_exr(exr, ex, prov);
  std::vector<std::filesystem::path> written = {exr};
  if (png.empty()) return written;
  write_tonemapped_png(png, ex.width, ex.height, ex.data[0], ex.data[1], ex.data[2], exposure, "reinhard");
  written.push_back(png);
  if (!exposure_rule.empty())
    written.push_back(write_tone_map_side_file(png, "reinhard v/(1+v) on linear RGB, then the sRGB transfer curve",
                                               exposure, exposure_rule, exr.filename().string()));
  return written;
}

}  // namespace atmosh::io
