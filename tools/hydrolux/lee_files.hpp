#pragma once
// The CLI's side of the Lee tables (the files' format itself is hydrolux/io/lee_files.hpp): the
// files encoded through the image plugin and written where hydrolux lee and export put them, and the
// memory check that names --size (hydrolux sky reads tables back through io/sky_job.hpp).
#include <string>
#include <vector>

#include "common.hpp"
#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::cli {

// io::encode_lee_files with the image plugin's encoder.
io::LeeFileBytes encode_lee_files(const atmos::LeeTable& t, const atmos::LeeImages& im);

// hydrolux lee's --wavelengths-nm "A:B" or "A:B:N" set on `spec` (the range, and N samples when
// given); Error naming the flag otherwise.
void set_wavelengths_flag(atmos::LeeSpec& spec, const std::string& text);

// hydrolux lee's files: -o's .exr and the .png and .json beside it, reserved in `files` before the
// work (the image plugin is loaded then too) and written after it.
// With a .nc path instead: the one NetCDF-4 file of io::lee_dataset (its history the command
// line), through the NetCDF plugin (loaded then too).
struct LeeOutputs {
  std::string exr_path, png_path, json_path;
  ImageOutput exr{}, png{};
  io::OutputFile* sidecar = nullptr;
  io::OutputFile* netcdf = nullptr;  // -o *.nc: the only output
  void write(const atmos::LeeTable& t, const atmos::LeeImages& im) const;
  std::string describe() const;  // what was written, for the closing line
};
LeeOutputs declare_lee_outputs(io::FileSet& files, const std::string& path);

// A computed table's files for an engine, written into `dir` as <name>.exr, .png, .f32 and .json (the
// sidecar naming the raw copy and its layout), and for a Stokes table (LeeSpec::stokes) <name>_q.f32,
// its Q as the compositor's RGB (scene::bow_table's q) in the .f32's layout: hydrolux export.
// Returns the table's manifest entry.
nlohmann::json write_engine_table(io::OutputDirectory& dir, const std::string& name, const atmos::LeeTable& t);

// atmos::check_table_memory in the CLI's words (--size WxH): hydrolux export's tables.
void check_table_memory(const std::vector<const atmos::LeeSpec*>& specs, const std::string& size_text);

}  // namespace hydrolux::cli
