// Bad input is bad input on either device: what a GPU pass of `atmosh gi render` finds
// wrong with the scene or the view exits 2 with one line naming it, as on the CPU, never
// "--device gpu: ..." (exit 1, taken for a missing GPU); and gi::render_method checks the
// view before its first pass, the radiosity volume's build included.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../apps/run_cli.hpp"
#include "atmosh/error.hpp"
#include "atmosh/gi/driver.hpp"
#include "atmosh/gi/methods.hpp"

namespace {
using atmosh::test::run_cli;
namespace gi = atmosh::gi;

TEST(GiBadInputDevice, ASceneWithoutExtentIsBadInputOnEveryDevice) {
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_bad_device", "extent");
  // One triangle with its three corners at one point: a valid mesh file whose bounding box
  // is empty, which the light propagation volume cannot be laid over.
  const auto obj = dir / "point.obj";
  std::ofstream(obj) << "v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n";
  for (const char* device : {"cpu", "gpu", "auto"}) {
    const std::string args = "gi render --mesh '" + obj.string() + "' --method lpv --grid 4 --pixel-samples 1 " +
                             "--size 8x8 --device " + device + " -o '" + (dir / "x.exr").string() + "'";
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_EQ(atmosh::test::count_lines(r.err), 1) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("bounding box is empty"), std::string::npos) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("--device"), std::string::npos) << args << "\n" << r.err;  // not taken for a missing GPU
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "x.exr"));
}

TEST(GiBadInputDevice, RenderMethodChecksTheViewBeforeItsFirstPass) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::MethodOptions m;
  m.method = "radiosity";
  m.grid = 64;  // a volume of 64^3 probes x 6 x 128^2 rays: hours, were it built first
  m.cube_size = 128;
  for (auto device : {atmosh::DeviceRequest::gpu, atmosh::DeviceRequest::automatic, atmosh::DeviceRequest::cpu}) {
    m.device = device;
    try {
      gi::render_method(s, s.camera, 0, 8, m);
      ADD_FAILURE() << "an image of width 0 was rendered";
    } catch (const atmosh::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("0x8"), std::string::npos) << e.what();
    }
  }
  gi::Camera blind = s.camera;
  blind.up = blind.forward;  // no image plane
  m.method = "lpv";
  m.device = atmosh::DeviceRequest::gpu;
  EXPECT_THROW(gi::render_method(s, blind, 8, 8, m), atmosh::InputError);
}

// gi::converge_methods builds every probe grid at the most bands of its list: a library
// caller's empty list is bad input naming the option, found before the reference render.
TEST(GiBadInputDevice, ConvergeRejectsAnEmptyBandsListBeforeAnyWork) {
  const gi::Scene s = gi::builtin_scene("cornell-box");
  gi::ConvergeOptions c;
  c.bands.clear();
  const auto dir = atmosh::test::scratch_dir("atmosh_gi_bad_device", "converge");
  std::vector<std::string> steps;
  try {
    gi::converge_methods(s, 6, 6, c, dir, [&](const std::string& name, const auto& work) {
      steps.push_back(name);
      work({});
    });
    ADD_FAILURE() << "an empty bands list was studied";
  } catch (const atmosh::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--bands-list"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(steps.empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "reference.exr"));
}

}  // namespace
