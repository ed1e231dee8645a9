// atmosh/scene/sweep.hpp — declarative parameter sweeps over scenes.
//
// A sweep file (TOML, version 1) names a base scene and parameters, each a dotted
// scene key with its values:
//
//   version = 1
//   scene = "base.toml"          # relative to the sweep file; default: built-in scene
//   mode = "grid"                # "grid" (cartesian product) or "zip" (i-th values together)
//   [[parameter]]
//   key = "sun.elevation_deg"
//   values = [0.0, 2.0, 5.0]     # or: from = 0, to = 10, step = 2   (or count = 6)
//   [[parameter]]
//   key = "mie.scattering_per_m"
//   values = [2e-6, 4e-6, 8e-6]
//
// Points are numbered 0..N-1 in a fixed order (last parameter fastest). Each point's
// scene is validated up front, so a bad value fails before any work (exit 2 with
// the key). Results: one tidy CSV, a row per point: `point`, one column per
// parameter key, the evaluator's named outputs, `time_s`.
//
// Resumable: each finished point is appended (and fsync'ed) to a journal beside the
// output; `resume` skips the points the journal holds and drops a torn last line,
// so no row is lost or duplicated after a kill. Shardable: shard k of n takes the
// points with index % n == k - 1; `merge_sweep` joins shard files and checks that
// every point appears exactly once.
//
// Identity: every sweep has a `sweep_id` (sweep_identity below), a 64-bit FNV-1a hash
// (atmosh/io/hash.hpp) of its normalized content: the parameter keys and every
// point's values (so comments, layout and `values` vs `from/to/step` do not matter),
// the base scene it resolves to (parsed and re-serialized: key order and comments do
// not matter), and every setting that changes results (SweepOptions::settings:
// the CLI passes the table shells, view-ray segments, samples per segment and the
// largest piece optical depth; wavelengths are part of the scene). The id is the
// first line of the journal and a provenance line of every shard and merged CSV,
// next to `sweep`, `base_scene` and the settings. A resume whose journal or CSV
// holds another id, and a merge of shards with different ids, are refused
// (InputError naming both ids and the file). Resuming a completed sweep (its CSV
// holds every point of the shard) recomputes nothing and leaves the CSV as it is.
//
// Range values (from/to/step or count) are rounded to 15 significant digits, so
// that from = 2e-6, step = 2e-6 gives exactly 8e-6 (not 7.999999999999999e-06);
// every value column prints the shortest form that reads back to the same double
// (atmosh/format.hpp).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "atmosh/progress.hpp"
#include "atmosh/scene/scene.hpp"

namespace atmosh::scene {

struct SweepSpec {
  std::string source;                       // sweep file name
  std::string base_scene_text;              // TOML of the base scene
  std::string base_scene_source;
  std::vector<std::string> keys;            // parameter keys, in file order
  std::vector<std::vector<Override>> points;
};

SweepSpec load_sweep(const std::filesystem::path& file);
SweepSpec parse_sweep(std::string_view toml_text, const std::string& source_name,
                      const std::filesystem::path& base_dir);

// Named outputs of one point, in a fixed order (the same for every point).
using SweepOutputs = std::vector<std::pair<std::string, double>>;
using SweepEvaluator = std::function<SweepOutputs(const Scene&)>;

// Named settings that change results, in a fixed order, e.g. {"lut_shells", "32"}.
using SweepSettings = std::vector<std::pair<std::string, std::string>>;

// The sweep's identity: 16 hex digits (see above).
std::string sweep_identity(const SweepSpec& spec, const SweepSettings& settings);


struct SweepOptions {
  std::filesystem::path out_dir;
  SweepSettings settings;      // recorded in the CSV and part of the identity
  // Optional: the fraction of the shard's points finished (resumed ones included),
  // called from worker threads under a lock.
  ProgressCallback progress;
  bool resume = false;
  int shard = 1, shards = 1;   // shard k of n, 1-based
  int threads = 1;             // workers; 0 = the CPUs this process may use (atmosh::resolve_threads)
  // shard and shards from "k/N" (InputError "--shard '<text>' is not k/N"; the range is
  // checked by run_sweep).
  void set_shard(const std::string& text);
};

struct SweepResult {
  std::filesystem::path csv;
  int points_total = 0;      // in the whole sweep
  int points_in_shard = 0;
  int points_resumed = 0;    // taken from the journal
  int points_computed = 0;
  std::string sweep_id;
};

// Evaluates the points (in parallel when threads > 1); the evaluator must be
// thread-safe. Output: out_dir/sweep.csv, or sweep.shard-K-of-N.csv for shards.
SweepResult run_sweep(const SweepSpec& spec, const SweepEvaluator& eval, const SweepOptions& opt);

// Joins shard CSVs into one, sorted by point; InputError if a point is missing,
// duplicated, or the files come from different sweeps (different `sweep_id`, or
// none). The merged CSV keeps the shards' sweep provenance (sweep, base_scene,
// sweep_id, settings).
void merge_sweep(const std::vector<std::filesystem::path>& inputs, const std::filesystem::path& output);

}  // namespace atmosh::scene
