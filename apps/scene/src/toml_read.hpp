// Internal to atmosh_scene: the one way scene and sweep files reach the TOML parser.
#pragma once

#include <toml++/toml.h>

#include <string>
#include <string_view>

namespace atmosh::scene::detail {

// check_toml_limits, then toml::parse; a syntax error becomes an InputError
// "<source>:<line>:<column>: TOML syntax error: <first line of the parser's message>".
toml::table parse_toml_checked(std::string_view text, const std::string& source_name);

}  // namespace atmosh::scene::detail
