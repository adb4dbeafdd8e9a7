#pragma once
// The sun and sky parameters an engine draws the scene from, as JSON (hydrolux export's sky.json):
// the model's constants, the rain's extinction law, the tone map, and for every whole degree of the
// sun's elevation from 0 to 90 the sun's and the sky's light and Preetham's coefficients, the sky's
// polarisation model (scene::sky_dolp, for a polariser) (docs/sky.md);
// and the shaders beside it.
#include <nlohmann/json.hpp>

#include <string>

#include "hydrolux/io/files.hpp"
#include "hydrolux/scene/bow_tables.hpp"

namespace hydrolux::io {

// Throws DomainError for a turbidity outside the model's range (scene::make_sun_sky).
nlohmann::json sky_parameters_json(double turbidity);

// The non-spherical drops' 3-D rainbow table (scene::compute_shaped_rainbow_table) as engines read
// it: `name`.f32 (little-endian float32, positions x rows x columns x 3) and `name`.json (the axes:
// radius_um, angle_deg, position_deg; the shape, the sun's elevation, the layout), and when the table
// has the Stokes Q (ShapedRainbowTable::q) `name`_q.f32 in the same layout; returns the manifest's
// entry for it. data/shaders/README.md describes them.
nlohmann::json write_shaped_rainbow_table(OutputDirectory& dir, const std::string& name,
                                          const scene::ShapedRainbowTable& t);

// The shaders that evaluate the scene (data/shaders/: the GLSL and HLSL folders and the files beside
// them) written into `dir` under their names there; returns the names, for the assets' manifest.
nlohmann::json write_engine_shaders(OutputDirectory& dir);

}  // namespace hydrolux::io
