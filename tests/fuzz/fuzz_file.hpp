// Readers that take a path get the fuzzer's bytes through a file of this process.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace atmosh::fuzz {

// Writes the bytes to <tmp>/atmosh-fuzz-<pid><ext> (overwritten on every input).
inline std::filesystem::path write_input(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  static const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("atmosh-fuzz-" + std::to_string(::getpid()) + ext);
  std::ofstream(file, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                static_cast<std::streamsize>(size));
  return file;
}

}  // namespace atmosh::fuzz
