// Fuzzes the SH coefficient CSV reader (`sh eval|rotate|irradiance`, `prt relight
// --light`): any text must give consistent coefficients or throw atmosh::InputError.
#include <cstddef>
#include <cstdint>
#include <string>

#include "atmosh/error.hpp"
#include "fuzz_repeat.hpp"
#include "atmosh/io/sh_coefficients.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto c = atmosh::io::parse_sh_coefficients(text, "fuzz.csv");
    const std::size_t n = static_cast<std::size_t>(c.bands) * static_cast<std::size_t>(c.bands);
    if (c.bands < 1 || c.names.size() != c.channels.size()) __builtin_trap();
    for (const auto& ch : c.channels)
      if (ch.size() != n) __builtin_trap();
    (void)atmosh::io::parse_sh_light(text, "fuzz.csv", 3);
  } catch (const atmosh::InputError&) {
  }
  return 0;
}
