// Output paths checked before any work (atmosh/io/output_check.hpp).
#include "atmosh/io/output_check.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>

#include "atmosh/error.hpp"

namespace atmosh::io {

namespace {
// The nearest existing folder at or above p.
std::filesystem::path existing_ancestor(std::filesystem::path p) {
  std::error_code ec;
  if (p.empty()) p = ".";
  p = std::filesystem::absolute(p, ec);
  while (!p.empty() && !std::filesystem::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
  return p;
}
}  // namespace

void check_output_dir(const std::filesystem::path& dir, const std::string& what) {
  std::error_code ec;
  const std::string name = dir.string();
  if (std::filesystem::exists(dir, ec)) {
    if (!std::filesystem::is_directory(dir, ec)) throw InputError(what + " '" + name + "': exists and is not a folder");
    if (::access(dir.c_str(), W_OK | X_OK) != 0) throw InputError(what + " '" + name + "': folder is not writable");
    return;
  }
  const auto up = existing_ancestor(dir);
  if (!std::filesystem::is_directory(up, ec))
    throw InputError(what + " '" + name + "': '" + up.string() + "' is not a folder");
  if (::access(up.c_str(), W_OK | X_OK) != 0)
    throw InputError(what + " '" + name + "': cannot be created ('" + up.string() + "' is not writable)");
}

void check_output_file(const std::filesystem::path& file, const std::vector<std::string>& extensions,
                       const std::string& what) {
  std::error_code ec;
  const std::string name = file.string();
  if (file.empty() || !file.has_filename()) throw InputError(what + " '" + name + "': not a file name");
  if (std::filesystem::is_directory(file, ec)) throw InputError(what + " '" + name + "': is a folder, not a file");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!extensions.empty() && std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
    std::string list;
    for (const auto& x : extensions) list += (list.empty() ? "" : ", ") + x;
    throw InputError(what + " '" + name + "': extension '" + ext + "' is not " + list);
  }
  const auto parent = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  check_output_dir(parent, what);
}

void check_study_stem(const std::filesystem::path& stem, const std::string& what) {
  std::error_code ec;
  const std::string name = stem.string();
  if (stem.empty() || !stem.has_filename()) throw InputError(what + " '" + name + "': not a file name (the stem of STEM.csv and STEM.png)");
  if (std::filesystem::is_directory(stem, ec))
    throw InputError(what + " '" + name + "': is a folder; give a stem such as " + (stem / "convergence").string() +
                     " (writes STEM.csv and STEM.png)");
  for (const char* ext : {".csv", ".png"}) {
    std::filesystem::path f = stem;
    f += ext;
    check_output_file(f, {ext}, what);
  }
}

}  // namespace atmosh::io
