#pragma once
// A rainbow scene rendered to a file, as `hydrolux sky` makes it (docs/sky.md): the tables given
// (--lut) or computed for the scene's radius, the moisture mask and environment read, the frame
// composited (scene/compositor.hpp) and written as a linear EXR (cd/m^2) or a tone-mapped PNG. Every
// file is declared before any work (io/files.hpp): nothing is written over an input, no output is
// left half written. The doors only translate: the CLI parses its flags into a SkyJob and prints what
// the hooks and the result say; the checks are the scene's (scene/sky_scene.hpp), in the flags' words.
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/io/image_io.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux::io {

// What to render and where, as the CLI's flags name them (messages quote them so).
struct SkyJob {
  scene::SkyOptions options;            // the declared values (scene/sky_params.hpp) and the shape
  std::vector<std::string> luts;        // --lut: Lee tables (.exr with the .json beside it)
  std::optional<std::string> moisture, environment;
  std::string output;                   // -o: .png (tone-mapped) or .exr (cd/m^2)
  // The declared parameters the user gave (by name): one given where nothing uses it is refused.
  std::set<std::string, std::less<>> given;
};

struct SkyJobHooks {
  ImageCodec codec;  // image_io.hpp: the library does not load OpenImageIO itself
  // Called once the request is checked and its files declared, before anything is read or computed:
  // the CLI loads its image plugin then, so a missing one is reported before the tables' work.
  std::function<void()> codec_ready;
  std::function<void(const std::string&)> warn;            // the codec's warnings, one line each
  std::function<void(double, std::string_view)> progress;  // the tables' work, fraction done; may be empty
  std::function<void()> finish_progress;
};

struct SkyJobResult {
  scene::SkySettings settings;   // as rendered
  std::string output;            // the file written
  std::string shape;             // the drops' shape name (atmos::drop_shape_name)
  bool shaped = false;           // non-spherical drops: the bow at `positions` position angles
  int positions = 1;
  double optical_depth = 0;      // the curtain's, projected area
  double sun_illuminance_lux = 0;
  double render_ms = 0, bake_ms = 0;
  double seconds = 0;            // in all
  // The bow profiles' estimated error (scene::largest_error: RMS in luminance, relative), computed
  // profiles only (none with --lut); the largest sampling they were computed at, whether it was chosen
  // (no --sampling) and, where automatic sampling computed some twice, the largest first-pass estimate
  // (scene::profile_accuracy).
  std::optional<double> profile_error;
  double profile_sampling = 0;
  bool sampling_automatic = false;
  std::optional<double> profile_first_error;
};

// Runs the job. Error (bad input, before anything is written), IoError, IoFailure (the system failed
// midway; nothing replaced) as io/files.hpp says.
SkyJobResult run_sky_job(const SkyJob& job, const SkyJobHooks& hooks);

// The one line a run's summary is (the CLI prints it unless quiet).
std::string sky_summary(const SkyJobResult& result);

// A Lee table read back for the compositor: `exr_path` and the sidecar beside it (same name, .json),
// through parse_lee_sidecar and lee_bow_table (lee_files.hpp), decoded by `codec`. Errors name
// `flag`, the file and what is wrong with it.
scene::BowTable read_lee_lut(const ImageCodec& codec, const std::string& flag, const std::string& exr_path,
                             const std::function<void(const std::string&)>& warn = {});

// The scene's tables from --lut files, read one by one in the order given (each checked before the
// next is read): one rainbow table whose radii cover `radius_um` and optionally a corona table, each
// sliced at that radius (the corona's empty outside its radii). Errors name --lut, --radius-um and,
// when `corona` is on and no corona table covers the radius, --corona.
struct SkySlices {
  scene::BowSlice rainbow, corona;
};
SkySlices read_sky_luts(const ImageCodec& codec, const std::vector<std::string>& luts, double radius_um, bool corona,
                        const std::function<void(const std::string&)>& warn = {});

}  // namespace hydrolux::io
