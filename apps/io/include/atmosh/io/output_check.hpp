// atmosh/io/output_check.hpp — output paths checked before any work, so that a long
// run does not end in a write error: the folder exists or can be made and is writable,
// a file name is not a folder, and its extension is an expected one.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace atmosh::io {

/// `dir` is a writable folder, or can be created (its nearest existing ancestor is a
/// writable folder). InputError "<what> '<dir>': <why>" otherwise (exists and is not a
/// folder; folder is not writable; cannot be created ('<ancestor>' is not writable)).
void check_output_dir(const std::filesystem::path& dir, const std::string& what);

/// `file` names a file (not a folder), its extension (compared in lower case) is one
/// of `extensions` (e.g. {".exr"}; empty: any), and its folder passes
/// check_output_dir. InputError naming `what` (e.g. the option, "-o") otherwise.
void check_output_file(const std::filesystem::path& file, const std::vector<std::string>& extensions,
                       const std::string& what);

/// An output stem that a study writes as STEM.csv and STEM.png (io::write_study: error
/// against run time, `converge *`, `sun accuracy`, `prt converge`): `stem` names a file
/// name (not a folder), neither STEM.csv nor STEM.png is a folder, and the stem's folder
/// passes check_output_dir. InputError naming `what` otherwise.
void check_study_stem(const std::filesystem::path& stem, const std::string& what);

}  // namespace atmosh::io
