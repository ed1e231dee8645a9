// atmosh/scene/toml_limits.hpp — bounds every TOML file (scene, sweep) is held to
// before it reaches the TOML parser.
//
// The parser builds one nested table per part of a dotted key or table header and
// recurses through them; a hostile file of 40 000 parts (80 KB) overflows the stack.
// check_toml_limits scans the text once, without recursion, respecting strings
// (basic, literal, multi-line) and comments, and throws atmosh::InputError
//   "<source>:<line>: key path has 40000 parts (this reader's limit is 64)"
// when a key path or table header has too many parts or bytes, when arrays and
// inline tables nest too deeply, or when a value's depth (table header parts + the
// parts of every key that opens it + nesting) exceeds the limit. The scene schema
// needs at most 4 parts and 1 level of nesting, so the limits only stop abuse.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace atmosh::scene {

struct TomlLimits {
  std::size_t max_bytes = 16u << 20;   // whole file
  std::size_t max_key_parts = 64;      // parts of one dotted key or table header
  std::size_t max_key_bytes = 1024;    // bytes of one dotted key or table header
  std::size_t max_nesting = 64;        // arrays and inline tables inside one another
  std::size_t max_depth = 128;         // tables + arrays a value sits in, in all
};

// Throws InputError naming source_name, the line and the limit exceeded.
void check_toml_limits(std::string_view text, const std::string& source_name, const TomlLimits& limits = {});

// Reads a TOML file as text (scene or sweep; `what` names it in messages), refusing
// one larger than limits.max_bytes before reading it. InputError if unreadable.
std::string read_toml_file(const std::filesystem::path& file, const std::string& what,
                           const TomlLimits& limits = {});

}  // namespace atmosh::scene
