// Output paths checked before any work (atmosh/io/output_check.hpp): each refusal is an
// InputError whose message names the option and the path, and acceptable paths
// (existing folders, folders that can be created, known extensions in any case) pass.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <unistd.h>

#include "atmosh/error.hpp"
#include "atmosh/io/output_check.hpp"

namespace fs = std::filesystem;

namespace {
fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("atmosh_output_check_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const atmosh::InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(OutputCheck, AcceptsExistingAndCreatableFolders) {
  const fs::path d = scratch();
  EXPECT_NO_THROW(atmosh::io::check_output_dir(d, "-o"));
  EXPECT_NO_THROW(atmosh::io::check_output_dir(d / "a" / "b", "-o"));  // created later by the writer
  EXPECT_FALSE(fs::exists(d / "a"));                                    // a check creates nothing
  EXPECT_NO_THROW(atmosh::io::check_output_file(d / "new" / "sky.EXR", {".exr"}, "-o"));
  EXPECT_NO_THROW(atmosh::io::check_output_file(d / "any.bin", {}, "-o"));
  fs::remove_all(d);
}

TEST(OutputCheck, RefusalsNameTheOptionAndThePath) {
  const fs::path d = scratch();
  const fs::path file = d / "plain.txt";
  std::ofstream(file) << "x";
  EXPECT_EQ(refusal([&] { atmosh::io::check_output_dir(file, "-o"); }),
            "-o '" + file.string() + "': exists and is not a folder");
  EXPECT_EQ(refusal([&] { atmosh::io::check_output_file(d, {".exr"}, "--png"); }),
            "--png '" + d.string() + "': is a folder, not a file");
  EXPECT_EQ(refusal([&] { atmosh::io::check_output_file(d / "x.png", {".exr", ".hdr"}, "-o"); }),
            "-o '" + (d / "x.png").string() + "': extension '.png' is not .exr, .hdr");
  EXPECT_EQ(refusal([&] { atmosh::io::check_output_file(file / "x.exr", {".exr"}, "-o"); }),
            "-o '" + file.string() + "': exists and is not a folder");  // its folder is a file
  EXPECT_EQ(refusal([&] { atmosh::io::check_output_file(fs::path(), {".exr"}, "-o"); }), "-o '': not a file name");
  fs::remove_all(d);
}

// A study's stem (STEM.csv and STEM.png, io::write_study): a stem in a writable folder
// passes; a stem that is a folder, a STEM.png that is a folder, or a stem under a file
// is refused, naming the option and the path.
TEST(OutputCheck, StudyStems) {
  const fs::path d = scratch();
  const fs::path file = d / "plain.txt";
  std::ofstream(file) << "x";
  EXPECT_NO_THROW(atmosh::io::check_study_stem(d / "convergence", "-o"));
  EXPECT_NO_THROW(atmosh::io::check_study_stem(d / "new" / "convergence", "-o"));  // a folder made by the writer
  EXPECT_EQ(refusal([&] { atmosh::io::check_study_stem(d, "-o"); }),
            "-o '" + d.string() + "': is a folder; give a stem such as " + (d / "convergence").string() +
                " (writes STEM.csv and STEM.png)");
  fs::create_directories(d / "sky.png");
  EXPECT_EQ(refusal([&] { atmosh::io::check_study_stem(d / "sky", "-o"); }),
            "-o '" + (d / "sky.png").string() + "': is a folder, not a file");
  EXPECT_EQ(refusal([&] { atmosh::io::check_study_stem(file / "sky", "-o"); }),
            "-o '" + file.string() + "': exists and is not a folder");
  EXPECT_EQ(refusal([&] { atmosh::io::check_study_stem(fs::path(), "-o"); }),
            "-o '': not a file name (the stem of STEM.csv and STEM.png)");
  fs::remove_all(d);
}
