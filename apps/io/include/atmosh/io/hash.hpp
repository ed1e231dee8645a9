// atmosh/io/hash.hpp — the content hash behind the identities atmosh records
// (a sweep's `sweep_id`, see atmosh/scene/sweep.hpp).
//
// 64-bit FNV-1a (Fowler, Noll, Vo; offset basis 14695981039346656037, prime
// 1099511628211, as published at http://www.isthe.com/chongo/tech/comp/fnv/),
// printed as 16 lower-case hex digits. It detects accidental mixing of results
// (a resume or merge of a different sweep), not tampering: it is not cryptographic.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace atmosh::io {

class ContentHash {
 public:
  ContentHash& add(std::string_view bytes);
  // A field: its bytes and a separator that cannot occur in text ('\0'), so that
  // ("ab", "c") and ("a", "bc") hash differently.
  ContentHash& field(std::string_view bytes);
  std::uint64_t value() const { return h_; }
  std::string hex() const;  // 16 hex digits

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

}  // namespace atmosh::io
