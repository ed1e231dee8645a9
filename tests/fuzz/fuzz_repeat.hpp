// A custom libFuzzer mutator for text formats whose bugs hide in repetition: half
// of the mutations repeat a short piece of the input (up to a separator) 256 to
// 65536 times (log-uniform), so that `a.a.a...` keys, `[[[...` nesting or long lists
// are reached in seconds; the rest are libFuzzer's own mutations.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>

extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size,
                                               unsigned int seed) {
  std::minstd_rand rng(seed);
  if (size > 0 && size < max_size && rng() % 2 == 0) {
    // The piece: from a random byte to the next separator ('.', '[', '{', ',', newline)
    // within 16 bytes, so that `part.` or `[` repeats; else 1..8 bytes.
    const std::size_t at = rng() % size;
    std::size_t len = 1 + rng() % std::min<std::size_t>(size - at, 8);
    for (std::size_t k = at; k < size && k < at + 16; ++k)
      if (std::strchr(".[{,\n", data[k]) != nullptr && data[k] != 0) {
        len = k - at + 1;
        break;
      }
    const std::size_t times = std::min<std::size_t>(std::size_t{1} << (8 + rng() % 9), (max_size - size) / len);
    std::string out(reinterpret_cast<const char*>(data), at + len);
    for (std::size_t k = 0; k < times; ++k) out.append(reinterpret_cast<const char*>(data) + at, len);
    out.append(reinterpret_cast<const char*>(data) + at + len, size - at - len);
    std::memcpy(data, out.data(), out.size());
    return out.size();
  }
  return LLVMFuzzerMutate(data, size, max_size);
}
