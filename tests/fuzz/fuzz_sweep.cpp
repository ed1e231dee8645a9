// Fuzzes the sweep reader: any byte string must either give a sweep whose first
// points' scenes parse, or throw atmosh::InputError — never crash, hang or leak.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "atmosh/error.hpp"
#include "fuzz_repeat.hpp"
#include "atmosh/scene/scene.hpp"
#include "atmosh/scene/sweep.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    // A base folder that does not exist: a relative `scene = ...` cannot be read.
    const auto spec = atmosh::scene::parse_sweep(text, "fuzz-sweep.toml", "/nonexistent/atmosh-fuzz");
    for (std::size_t i = 0; i < spec.points.size() && i < 4; ++i)  // as run_sweep validates each point
      (void)atmosh::scene::parse_scene(spec.base_scene_text, "fuzz point", spec.points[i]);
  } catch (const atmosh::InputError&) {
  }
  return 0;
}
