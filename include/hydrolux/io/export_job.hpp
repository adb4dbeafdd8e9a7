#pragma once
// The engine assets `hydrolux export` writes into a folder (docs/sky.md): the scene's Lee tables
// (rainbow, corona and, for non-spherical drops, the 3-D rainbow table) as EXR, PNG, raw float32 and
// their JSON axes, sky.json, the shaders and the manifest naming them. The folder is staged beside its
// destination and appears complete or not at all (io/files.hpp). The CLI parses its flags into an
// ExportJob and prints what the hooks and the result say; the messages name the flags.
#include <nlohmann/json.hpp>

#include <array>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux::io {

struct ExportJob {
  scene::ExportOptions options;                 // the declared values (scene/sky_params.hpp) and the shape
  std::string dir;                              // --dir
  std::string theory = "mie";                   // --theory of the spheres' tables
  // The declared parameters the user gave (by name): --sun-elevation-deg is refused for spheres.
  std::set<std::string, std::less<>> given;
};

struct ExportJobHooks {
  ImageCodec codec;  // image_io.hpp: the library does not load OpenImageIO itself
  // Called once the folder is declared, before the work: the CLI loads its image plugin then.
  std::function<void()> codec_ready;
  std::function<void(double, std::string_view)> progress;  // the tables' work, fraction done; may be empty
  std::function<void()> finish_progress;
};

// The tables' specs a job asks for, checked (Error naming the flag).
struct ExportTables {
  atmos::LeeSpec rainbow, corona;
  bool with_corona = true;              // not for drops whose corona lies within 0.2 degrees of the sun
  atmos::DropShapeSpec shape;
  std::optional<atmos::LeeSpec> shaped;  // non-spherical drops: the 3-D table's spec
};
ExportTables export_tables(const ExportJob& job);

struct ExportJobResult {
  std::size_t files = 0;  // written into the folder
  bool with_corona = true, shaped = false;
  double seconds = 0;     // in all
};

// Runs the job: the specs checked, the memory and the turbidity, the folder declared, the tables
// computed and written with sky.json, the shaders and manifest.json, and the folder committed. Error
// (bad input, before anything is written), IoError, IoFailure as io/files.hpp says.
ExportJobResult run_export_job(const ExportJob& job, const ExportJobHooks& hooks);

// The one line a run's summary is (the CLI prints it unless quiet).
std::string export_summary(const ExportJob& job, const ExportJobResult& result);

// A computed table's files for an engine, written into `dir` as <name>.exr, .png, .f32 and .json (the
// sidecar naming the raw copy and its layout), and for a Stokes table (LeeSpec::stokes) <name>_q.f32,
// its Q as the compositor's RGB (scene::bow_table's q) in the .f32's layout; the images encoded by
// `encode`. Returns the table's manifest entry.
nlohmann::json write_engine_table(OutputDirectory& dir, const std::string& name, const atmos::LeeTable& t,
                                  const LeeImageEncoder& encode);

}  // namespace hydrolux::io
