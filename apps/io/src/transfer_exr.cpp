// Per-pixel transfer images (see transfer_exr.hpp).
#include "atmosh/io/transfer_exr.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"

namespace atmosh::io {

namespace {
std::string coefficient_channel(int l, int m) { return "sh_l" + std::to_string(l) + "_m" + std::to_string(m); }
}  // namespace

void write_transfer_exr(const std::filesystem::path& file, const TransferImage& t, const Provenance& prov) {
  const std::size_t K = static_cast<std::size_t>(t.bands) * static_cast<std::size_t>(t.bands);
  const std::size_t np = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  if (t.coefficients.size() != K || t.ao.size() != np || t.mask.size() != np)
    throw std::invalid_argument("write_transfer_exr: channels do not match bands and width x height");
  std::vector<std::string> names;
  for (int l = 0; l < t.bands; ++l)
    for (int m = -l; m <= l; ++m) names.push_back(coefficient_channel(l, m));
  names.push_back("ao");
  names.push_back("mask");
  ExrImage ex(t.width, t.height, names);
  for (std::size_t i = 0; i < K; ++i) {
    if (t.coefficients[i].size() != np) throw std::invalid_argument("write_transfer_exr: a coefficient channel has the wrong size");
    ex.data[i] = t.coefficients[i];
  }
  ex.data[K] = t.ao;
  ex.data[K + 1] = t.mask;
  for (const auto& [k, v] : t.attributes) ex.string_attributes["atmosh:" + k] = v;
  ex.string_attributes["atmosh:sh_convention"] = "real orthonormal, Condon-Shortley phase, index l(l+1)+m";
  write_exr(file, ex, prov);
}

TransferImage read_transfer_exr(const std::filesystem::path& file, std::size_t max_bytes) {
  ExrImage ex = read_exr(file, max_bytes);
  const auto find = [&](const std::string& n) {
    const auto it = std::find(ex.channels.begin(), ex.channels.end(), n);
    return it == ex.channels.end() ? std::string::npos : static_cast<std::size_t>(it - ex.channels.begin());
  };
  TransferImage t;
  t.width = ex.width;
  t.height = ex.height;
  for (int l = 0;; ++l) {
    std::vector<std::size_t> band;
    for (int m = -l; m <= l; ++m) {
      const std::size_t c = find(coefficient_channel(l, m));
      if (c == std::string::npos) break;
      band.push_back(c);
    }
    if (band.size() != static_cast<std::size_t>(2 * l + 1)) break;
    for (std::size_t c : band) t.coefficients.push_back(std::move(ex.data[c]));
    t.bands = l + 1;
  }
  const std::size_t ao = find("ao"), mask = find("mask");
  if (t.bands < 1 || ao == std::string::npos)
    throw InputError(file.string() + ": not a per-pixel transfer image (needs channels sh_l0_m0 ... and ao)");
  t.ao = std::move(ex.data[ao]);
  if (mask != std::string::npos) t.mask = std::move(ex.data[mask]);
  for (const auto& [k, v] : ex.string_attributes)
    if (k.rfind("atmosh:", 0) == 0) t.attributes[k.substr(7)] = v;
  return t;
}

}  // namespace atmosh::io
