// Fuzzes EXR input as `sh project` and `prt relight` read it (sky images and cube
// crosses): read_exr must return a consistent image or throw atmosh::InputError;
// what it returns must then unpack (cube cross) and project without a crash.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "atmosh/error.hpp"
#include "atmosh/io/exr.hpp"
#include "atmosh/sh/projection.hpp"
#include "fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = atmosh::fuzz::write_input(data, size, ".exr");
  try {
    const atmosh::io::ExrImage img = atmosh::io::read_exr(file, std::size_t{64} << 20);
    if (img.width < 1 || img.height < 1 || img.data.size() != img.channels.size()) __builtin_trap();
    const std::size_t n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height);
    std::vector<float> planar;
    for (const auto& c : img.data) {
      if (c.size() != n) __builtin_trap();
      for (float v : c) planar.push_back(std::isfinite(v) ? v : 0.0f);  // the CLI refuses non-finite pixels
    }
    if (img.channels.empty() || n > 4096) return 0;  // keep each input fast
    const atmosh::sh::ImageView view{img.width, img.height, static_cast<int>(img.channels.size()), planar.data()};
    if (img.width == 2 * img.height) (void)atmosh::sh::project_equirect(view, 2);
    if (img.width * 3 == img.height * 4 || img.width * 4 == img.height * 3) (void)atmosh::sh::unpack_cross(view);
  } catch (const atmosh::InputError&) {
  }
  return 0;
}
