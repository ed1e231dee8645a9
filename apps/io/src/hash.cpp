#include "atmosh/io/hash.hpp"

#include <cstdio>

namespace atmosh::io {

ContentHash& ContentHash::add(std::string_view bytes) {
  for (unsigned char c : bytes) {
    h_ ^= c;
    h_ *= 1099511628211ull;
  }
  return *this;
}

ContentHash& ContentHash::field(std::string_view bytes) {
  add(bytes);
  return add(std::string_view("\0", 1));
}

std::string ContentHash::hex() const {
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h_));
  return b;
}

}  // namespace atmosh::io
