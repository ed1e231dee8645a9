// Fuzzes the .obj mesh reader: any file must load as a valid mesh or throw
// atmosh::InputError naming the file — never crash inside the mesh library.
#include <cstddef>
#include <cstdint>

#include "atmosh/error.hpp"
#include "fuzz_repeat.hpp"
#include "atmosh/prt/mesh.hpp"
#include "fuzz_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = atmosh::fuzz::write_input(data, size, ".obj");
  try {
    (void)atmosh::prt::load_mesh(file);
  } catch (const atmosh::InputError&) {
  }
  return 0;
}
