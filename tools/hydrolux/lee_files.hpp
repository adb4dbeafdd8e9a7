#pragma once
// The files of a Lee table, shared by `hydrolux lee` (which writes them), `hydrolux export` (which
// writes them into an asset folder, with a raw float32 copy for engines) and `hydrolux sky` (which
// reads them back through --lut): the linear EXR, the display PNG and the JSON sidecar that holds
// the exact axes.
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::cli {

nlohmann::json to_json(const std::vector<double>& v);

// The sidecar describing a table, its files named `exr_name` and `png_name`.
nlohmann::json lee_sidecar(const atmos::LeeTable& t, const atmos::LeeImages& im, const std::string& exr_name,
                           const std::string& png_name);

// The bytes of a table's files: EXR (R, G, B, XYZ.X, XYZ.Y, XYZ.Z), PNG, and the raw RGB as
// little-endian float32 (rows x columns x 3, the EXR's R, G, B).
struct LeeFileBytes {
  std::string exr, png, f32;
};
LeeFileBytes encode_lee_files(const atmos::LeeTable& t, const atmos::LeeImages& im);

// The axes a sidecar describes. Throws Error naming what is missing or wrong (not JSON, not a
// hydrolux Lee table, an unknown kind, axes absent or of the wrong type).
struct LeeSidecarAxes {
  atmos::LeeTableKind kind = atmos::LeeTableKind::rainbow;
  atmos::AngleAxis axis = atmos::AngleAxis::angle;
  atmos::RadiusScale radius_scale = atmos::RadiusScale::log;
  std::vector<double> radius_um, rows;
};
LeeSidecarAxes parse_lee_sidecar(std::string_view json_text);

// Refuses, before the work, tables whose computation would not fit in the memory available
// (atmos::estimated_bytes, the largest of `specs`, which are computed one after the other): one line
// naming --size with `size_text` and a size that would fit, in the first spec's terms (the one
// --size sets; the others scale with it).
void check_table_memory(const std::vector<const atmos::LeeSpec*>& specs, const std::string& size_text);

// A table read back for the compositor: `exr_path` and the sidecar beside it (same name, .json).
// The file must be OpenEXR by its content (a PNG renamed .exr holds display values, not sr^-1);
// the sidecar's axes and the values are checked by scene::bow_table (finite, strictly increasing,
// uniform on their scale, values non-negative). Errors name `flag`, the file
// and what is wrong with it.
scene::BowTable read_lee_lut(const std::string& flag, const std::string& exr_path);

}  // namespace hydrolux::cli
