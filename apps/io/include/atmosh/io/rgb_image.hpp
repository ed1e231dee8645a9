// atmosh/io/rgb_image.hpp — the one writer of a linear-RGB image: the EXR (its first
// three channels R, G, B, then any others) and, when asked, a tone-mapped PNG beside it
// (Reinhard v/(1+v) on linear RGB at an exposure, then the sRGB transfer curve) with,
// when an exposure rule is given, its side file <png>.json (io::write_tone_map_side_file).
// Used by the relit PRT frames and the gi images.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "atmosh/io/exr.hpp"
#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

// The exposure that maps the 99th percentile of the values to 1 (1 when it is not > 0
// or there are no values).
double percentile_exposure(std::vector<float> values);

// Writes `image` to exr; if png is non-empty, the tone-mapped PNG of channels 0, 1, 2 at
// `exposure`, and if exposure_rule is non-empty the side file recording it. Returns the
// files written (exr, png, side file).
std::vector<std::filesystem::path> write_rgb_image(const std::filesystem::path& exr, const ExrImage& image,
                                                   const std::filesystem::path& png, double exposure,
                                                   const std::string& exposure_rule, const Provenance& prov);

}  // namespace atmosh::io
