#pragma once
// The sun and sky parameters an engine draws the scene from, as JSON (hydrolux export's sky.json):
// the model's constants, the rain's extinction law, the tone map, and for every whole degree of the
// sun's elevation from 0 to 90 the sun's and the sky's light and Preetham's coefficients (docs/sky.md);
// and the shaders beside it.
#include <nlohmann/json.hpp>

#include "hydrolux/io/files.hpp"

namespace hydrolux::io {

// Throws DomainError for a turbidity outside the model's range (scene::make_sun_sky).
nlohmann::json sky_parameters_json(double turbidity);

// The shaders that evaluate the scene (data/shaders/: the GLSL and HLSL folders and the files beside
// them) written into `dir` under their names there; returns the names, for the assets' manifest.
nlohmann::json write_engine_shaders(OutputDirectory& dir);

}  // namespace hydrolux::io
