// Fuzzes the scene reader: any byte string must either parse or throw
// atmosh::InputError — never crash, hang, leak or throw anything else.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "atmosh/error.hpp"
#include "fuzz_repeat.hpp"
#include "atmosh/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto s = atmosh::scene::parse_scene(text, "fuzz.toml");
    (void)atmosh::scene::plan(s);
    (void)atmosh::scene::parse_scene(atmosh::scene::to_toml(s), "fuzz-roundtrip.toml");
  } catch (const atmosh::InputError&) {
  }
  return 0;
}
