// atmosh/io/atomic.hpp — atomic file output.
//
// Every file atmosh writes goes through write_atomically(): the writer callback
// fills a temporary file in the target's own folder (same file system), which is
// then renamed over the target. A run killed or failing half-way leaves either the
// old file or none, never a half-written one; the temporary is removed on error.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace atmosh::io {

// Calls writer(tmp_path) and renames tmp_path to target. The temporary keeps the
// target's extension (libraries such as OpenCV choose the format by it). Creates
// the target's parent folder if needed. Rethrows whatever writer throws, after
// removing the temporary.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& writer);

// Convenience: writes text atomically.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace atmosh::io
