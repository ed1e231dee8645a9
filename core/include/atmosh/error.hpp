// atmosh/error.hpp — the typed errors every atmosh library throws.
//
// Libraries never print or exit. They throw:
//   * atmosh::InputError  — the caller passed a bad value (NaN direction, band
//     count <= 0, negative density, a year outside an algorithm's range...).
//     The message is one line and names the offending value; the CLI maps it
//     to exit code 2.
//   * anything else derived from std::exception — an internal or I/O failure;
//     the CLI maps it to exit code 1.
#pragma once

#include <stdexcept>
#include <string>

namespace atmosh {

class InputError : public std::invalid_argument {
 public:
  explicit InputError(const std::string& message) : std::invalid_argument(message) {}
};

}  // namespace atmosh
