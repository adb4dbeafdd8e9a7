#pragma once
// The files of a Lee table (atmos/lee.hpp): the linear EXR, the display PNG, a raw float32 copy for
// engines, and the JSON sidecar that holds the exact axes. `hydrolux lee` and `hydrolux export`
// write them, `hydrolux sky --lut` reads them back.
//
// Nothing here opens a file or links an image codec: the caller passes the encoder in
// (encode_lee_files) and the decoded EXR and the sidecar's text in (parse_lee_sidecar,
// lee_bow_table), so the CLI can keep OpenImageIO in its plugin.
#include <nlohmann/json.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/dataset.hpp"
#include "hydrolux/core/image.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::io {

nlohmann::json to_json(const std::vector<double>& v);

// The sidecar describing a table, its files named `exr_name` and `png_name`.
nlohmann::json lee_sidecar(const atmos::LeeTable& t, const atmos::LeeImages& im, const std::string& exr_name,
                           const std::string& png_name);

// The table as a labelled dataset with CF-1.8 attributes (hydrolux lee -o table.nc through
// io/netcdf.hpp, and Python's atmos::LeeTable.to_xarray()): dimensions scattering_angle (rows), radius
// (columns), wavelength, channel (R, G, B) and xyz_component (X, Y, Z); coordinates with units and
// long names (cos_scattering_angle, and axis_ratio for non-spherical drops, as auxiliary
// coordinates); rgb, xyz and display as the EXR and PNG hold them (rgb gamut-mapped, float64; display
// float32), q_xyz and dolp with stokes; xyz_to_rgb and sun_white_xyz; the sidecar's settings as
// global attributes, with `history` as given (io: core/dataset.hpp's history_line).
Dataset lee_dataset(const atmos::LeeTable& t, const atmos::LeeImages& im, std::string_view history);

// One column's profile (hydrolux lee --json): its radius, the theory, the units, the colour space,
// and per row the angle, the RGB, the luminance and the XYZ.
nlohmann::json lee_profile_json(const atmos::LeeTable& t);

// The bytes of a table's files: EXR (R, G, B, XYZ.X, XYZ.Y, XYZ.Z), PNG, and the raw RGB as
// little-endian float32 (rows x columns x 3, the EXR's R, G, B).
struct LeeFileBytes {
  std::string exr, png, f32;
};
// Encodes an image in a file format (io::encode_image's signature; the CLI passes its image
// plugin's).
using LeeImageEncoder = std::function<std::string(const Image& image, ImageFormat format, PngOptions png)>;
LeeFileBytes encode_lee_files(const atmos::LeeTable& t, const atmos::LeeImages& im, const LeeImageEncoder& encode);

// The axes a sidecar describes. Throws Error naming what is missing or wrong (not JSON, not a
// hydrolux Lee table, an unknown kind, axes absent or of the wrong type).
struct LeeSidecarAxes {
  atmos::LeeTableKind kind = atmos::LeeTableKind::rainbow;
  atmos::AngleAxis axis = atmos::AngleAxis::angle;
  atmos::RadiusScale radius_scale = atmos::RadiusScale::log;
  std::vector<double> radius_um, rows;
  // A Stokes table's (the sidecar's "stokes" present): its XYZ -> RGB matrix (color_space.xyz_to_rgb),
  // which takes the EXR's Q.X, Q.Y, Q.Z to the compositor's RGB Q.
  std::optional<color::Mat3> stokes_xyz_to_rgb;
};
LeeSidecarAxes parse_lee_sidecar(std::string_view json_text);

// A table read back for the compositor from its sidecar's axes and its decoded EXR. The image must
// be OpenEXR by its content (a PNG renamed .exr holds display values, not sr^-1), with at least 3
// channels and one pixel per radius x row; the axes and the values are checked by scene::bow_table
// (finite, strictly increasing, uniform on their scale, values non-negative). A Stokes table's Q
// (channels Q.X, Q.Y, Q.Z by name) comes along as BowTable::q, its |Q_Y| at most I_Y. Throws Error
// saying what is wrong (without naming the file: the caller does).
scene::BowTable lee_bow_table(LeeSidecarAxes axes, const DecodedImage& decoded);

}  // namespace hydrolux::io
