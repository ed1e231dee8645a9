// atmosh/io/atomic.hpp — atomic file output.
//
// Every file atmosh writes goes through write_atomically(): the writer callback
// fills a temporary file in the target's own folder (same file system), which is
// then renamed over the target. A run killed or failing half-way leaves either the
// old file or none, never a half-written one; the temporary is removed on error.
// A run killed outright (SIGKILL, power loss) cannot remove its temporary
// (.NAME.tmp-PID-N.ext): the next write into the same folder removes every such
// file whose PID is no longer a running process on this machine (once per folder
// and process; a temporary of a live process is left alone).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace atmosh::io {

// Calls writer(tmp_path) and renames tmp_path to target. The temporary keeps the
// target's extension (libraries such as OpenCV choose the format by it). Creates
// the target's parent folder if needed. Rethrows whatever writer throws, after
// removing the temporary.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& writer);

// The PID in a temporary's name .NAME.tmp-PID-N[.ext], or nothing for another name.
std::optional<long> temporary_owner(const std::string& file_name);
// Removes the temporaries in dir whose PID is not a running process; returns how many.
int remove_stale_temporaries(const std::filesystem::path& dir);

// Convenience: writes text atomically.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

}  // namespace atmosh::io
