#pragma once
// A Lee table (atmos/lee.hpp) computed and written as `hydrolux lee` makes it (docs/lee.md): the
// request's texts parsed and checked in the flags' words, the table computed, and written as a linear
// EXR with the display PNG and the JSON sidecar beside it, or as one NetCDF-4 file; or one radius's
// profile printed as JSON. Every output is reserved before the work (io/files.hpp). The CLI parses its
// flags into a LeeJob, checks the medium and its temperature in its own words between lee_job_spec and
// run_lee_job, and prints what the hooks and the result say.
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/image_io.hpp"

namespace hydrolux::io {

// What to compute and where, as the CLI's flags name them (messages quote them so).
struct LeeJob {
  atmos::LeeRequest request;              // the declared values (--table, --radius-scale, ...), --shape, --size
  std::string theory = "mie";             // --theory
  std::optional<std::string> radius_um;   // --radius-um A:B or R
  std::string wavelengths = "380:780";    // --wavelengths-nm A:B[:N]
  std::string medium = "water";           // --medium (the door checks it against --temperature-c)
  std::string sun = "astm-g173-direct";   // --sun
  std::string color_space = "rec709";     // --color-space
  bool json = false;                      // --json: one radius's profile on standard output
  std::string output;                     // -o: .exr (with its .png and .json) or .nc
  // The declared parameters the user gave (by name): a non-spherical
  // drops' parameter given for spheres, or one with no effect, is refused.
  std::set<std::string, std::less<>> given;
  std::string command_line;  // the call, for a NetCDF file's history (core/dataset.hpp's history_line)
};

struct LeeJobHooks {
  ImageCodec codec;  // image_io.hpp: the library does not load OpenImageIO itself
  // Called once the outputs are reserved, before the work, for an image output (.exr): the CLI loads
  // its image plugin then, so a missing one is reported before the table's work.
  std::function<void()> codec_ready;
  std::function<void(std::string_view)> out;               // standard output (--json's profile)
  std::function<void(double, std::string_view)> progress;  // the table's work, fraction done; may be empty
  std::function<void()> finish_progress;
  // Each of atmos::lee_resolution_notes, once the job is checked and its outputs reserved, before the
  // work (the text names parameters between braces: the door spells them); may be empty.
  std::function<void(std::string_view)> warn;
};

struct LeeJobResult {
  std::string written;  // the files written, for the summary ("t.exr, t.png and t.json"); empty: none
  int columns = 0, rows = 0;
  std::string theory;   // scatter::theory_name
  double seconds = 0;   // the table's computation
  atmos::LeeWork work;  // evaluations, terms x angles
  atmos::LeeError error;  // the table's estimated error (LeeTable::error)
  // The sampling the table was computed at; with automatic sampling and a second pass, the first's
  // sampling and estimated error (LeeTable::first_sampling, first_error).
  double sampling = 1;
  std::optional<double> first_sampling, first_error;
};

// The table's spec from the job's texts and the declared values: the table, theory and shape, the
// spans, the size and the wavelengths, parsed and checked (Error naming the flag); the medium named,
// not yet checked.
atmos::LeeSpec lee_job_spec(const LeeJob& job);

// Runs the job on `spec` (lee_job_spec's, its medium checked by the door): the light source, the colour
// space and the remaining checks (the radii for the theory, the memory, -o or --json), the outputs
// reserved, the table computed, the profile printed (--json) and the files written and committed. Error
// (bad input, before anything is written), IoError, IoFailure as io/files.hpp says.
LeeJobResult run_lee_job(const LeeJob& job, atmos::LeeSpec spec, const LeeJobHooks& hooks);

// The one line a run's summary is (the CLI prints it when files were written, unless quiet).
std::string lee_summary(const LeeJobResult& result);

}  // namespace hydrolux::io
