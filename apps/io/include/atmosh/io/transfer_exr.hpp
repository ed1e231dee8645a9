// atmosh/io/transfer_exr.hpp — per-pixel diffuse transfer images (what `prt bake -o
// X.exr` writes and `prt relight X.exr` reads): an OpenEXR image of one camera view
// with one float channel per SH coefficient, "sh_l<l>_m<m>" in index order l(l+1)+m
// (real orthonormal SH, Condon-Shortley phase), then "ao" (the cosine-weighted
// visible fraction, in [0, 1]) and "mask" (1 where a surface is seen, else 0).
// Metadata are string attributes "atmosh:<key>" beside the provenance.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

struct TransferImage {
  int width = 0, height = 0;
  int bands = 0;                                // bands^2 coefficient channels
  std::vector<std::vector<float>> coefficients;  // [l(l+1)+m][y * width + x], row 0 at the top
  std::vector<float> ao;                         // [pixel]
  std::vector<float> mask;                       // [pixel]; empty when the file has no mask channel
  std::map<std::string, std::string> attributes;  // written as "atmosh:<key>" (quantity, view, samples, ...)
};

// The one writer (atomic, with provenance); the attribute sh_convention is added.
// Throws std::invalid_argument when the channels' sizes disagree with width x height.
void write_transfer_exr(const std::filesystem::path& file, const TransferImage& image, const Provenance& provenance);
// The one reader: the complete bands of sh_l*_m* channels (band l needs all 2l+1),
// ao and, if present, mask. InputError naming the file when it is not a transfer image
// (no sh_l0_m0 or no ao) or unreadable; max_bytes bounds what the EXR reader allocates.
TransferImage read_transfer_exr(const std::filesystem::path& file, std::size_t max_bytes = std::size_t{8} << 30);

}  // namespace atmosh::io
