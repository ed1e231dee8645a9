// atmosh/studies/studies_gi.hpp — the main job's scene-lighting step: the Cornell box lit
// by the default scene's sun and sky, rendered by every method of atmosh::gi, and a small
// error-against-run-time study of them against the path tracer.
#pragma once

#include <filesystem>
#include <vector>

namespace atmosh::studies {

/// Into `dir`: cornell_<method>.exr/.png (+ .png.json) for path (the reference), probes,
/// radiosity and lpv, and gi_converge.csv/.png. The sun (SPA at the default scene's observer)
/// and its direct-beam colour (transmitted solar spectrum, linear sRGB, Y in lux) and the sky
/// (3-band SH of its linear-sRGB radiance, cd/m^2) come from the default scene's sky model; the
/// box is turned so that its open side faces the sun's azimuth, and its ceiling light is off.
/// Returns the files written.
std::vector<std::filesystem::path> demo_gi(const std::filesystem::path& dir, bool quick);

}  // namespace atmosh::studies
