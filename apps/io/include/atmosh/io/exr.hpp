// atmosh/io/exr.hpp — OpenEXR images: float32, linear, named channels.
//
// Channel data are planar: data[c][y * width + x], row 0 at the top. Channel names
// follow OpenEXR custom: "R","G","B" for colour, plus any named channels such as
// "X","Y","Z", "L_550nm" (spectral radiance) or "sh_l2_m-1". Provenance entries are
// stored as string attributes "atmosh:<key>"; units and other metadata go in
// string_attributes / float_attributes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "atmosh/io/provenance.hpp"

namespace atmosh::io {

struct ExrImage {
  int width = 0;
  int height = 0;
  std::vector<std::string> channels;
  std::vector<std::vector<float>> data;
  std::map<std::string, std::string> string_attributes;
  std::map<std::string, float> float_attributes;

  ExrImage() = default;
  ExrImage(int w, int h, std::vector<std::string> channel_names);
  // Index of a channel, or -1.
  int find_channel(const std::string& name) const;
  std::vector<float>& channel(const std::string& name);  // throws if absent
  const std::vector<float>& channel(const std::string& name) const;
};

// Atomic write; provenance stored as "atmosh:<key>" string attributes.
void write_exr(const std::filesystem::path& file, const ExrImage& image, const Provenance& provenance);
// Largest side read_exr accepts (the project's image limit).
inline constexpr int kMaxExrSide = 65536;
// Bytes of an image of width x height x channels float32 values (what read_exr allocates).
std::size_t exr_image_bytes(std::int64_t width, std::int64_t height, std::size_t channels);
// Reads every channel as float32. Throws atmosh::InputError if unreadable, if the data
// window is empty or larger than kMaxExrSide a side, if a channel is subsampled, or if
// the image would need more than max_bytes (checked from the header, before reading).
ExrImage read_exr(const std::filesystem::path& file, std::size_t max_bytes = std::size_t{8} << 30);

}  // namespace atmosh::io
