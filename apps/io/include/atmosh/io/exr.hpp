// atmosh/io/exr.hpp — OpenEXR images: float32, linear, named channels.
//
// Channel data are planar: data[c][y * width + x], row 0 at the top. Channel names
// follow OpenEXR custom: "R","G","B" for colour, plus any named channels such as
// "X","Y","Z", "L_550nm" (spectral radiance) or "sh_l2_m-1". Provenance entries are
// stored as string attributes "atmosh:<key>"; units and other metadata go in
// string_attributes / float_attributes.
#pragma once

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
// Reads every channel as float32. Throws atmosh::InputError if unreadable.
ExrImage read_exr(const std::filesystem::path& file);

}  // namespace atmosh::io
