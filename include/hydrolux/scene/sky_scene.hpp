#pragma once
// A rainbow scene as a door asks for it (hydrolux sky's job, io/sky_job.hpp; hydrolux.sky in
// Python): the checks a request passes before any work, each in one wording whose parameters every
// door spells its own way; the tables computed for one radius; the frame's memory. The compositor
// (compositor.hpp) renders it.
//
// `door` names the parameters as the door does: Door::cli for the CLI ("--radius-um",
// "--shape"), Door::python for the library and Python ("radius_um", "shape"). A text the table
// does not declare (the shape, the environment) is spelled the same way: "--shape" or "shape"; the
// tables given from files, which only the CLI takes, are "--lut" or "hydrolux sky --lut".
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_params.hpp"

namespace hydrolux::scene {

// `name` (a declared parameter's or a text's, "radius_um", "shape") as `door` spells it.
std::string sky_word(std::string_view name, Door door);

// The checks of a scene, its settings already validated (validate(SkySettings)), for drops of
// `shape`, its tables given (hydrolux sky --lut: `tables_given`) or computed here: non-spherical
// drops' bow is computed here only (not with given tables), for a sun at most
// max_shape_sun_elevation_deg() up, and a radius within check_shape_radius; the spheres' tables
// computed here hold radii up to max_sky_radius_um(); a corona computed here needs drops of at most
// kCoronaMaxRadiusUm; and check_polarization's settings. Error (DomainError for check_shape_radius).
void check_sky_request(const SkyOptions& o, const atmos::DropShapeSpec& shape, bool tables_given,
                       Door door);

// A declared parameter given where nothing uses it is refused (given: never its default), saying
// why and what would use it: the tables' sampling with given tables, the sky's degree of
// polarisation without a polariser or the Stokes images, the environment's scale without an
// environment, the cube map's and the dome's sizes in another mode. `given(name)` says whether the
// user set the declared parameter `name`.
void refuse_unused_sky_params(const SkyOptions& o, const std::function<bool(std::string_view)>& given,
                              bool tables_given, bool environment_given, Door door);

// The frame too large for the memory left (available_memory_bytes(), or `available` when given) is
// refused before the work (estimated_bytes): one line naming the cube map's face size when the cube
// map is most of it, else the frame's size (as the door writes it: "--size 1280x720", "size (1280,
// 720)"), with what would fit.
void check_sky_memory(const SkySettings& s, Door door, double available = -1);

// The scene's tables computed for its radius (no tables given): the rainbow (of `shape` drops: the
// bow at kShapePositions position angles; of spheres, one profile) and, when the corona is on and
// its drops small enough, the corona; with the Stokes Q when a polariser or the Stokes images ask
// for it. `progress` rises from 0 to 1 over them, labelled as the library labels its work.
struct SkyTables {
  RainbowSlices rainbow;
  BowSlice corona;
};
SkyTables compute_sky_tables(const SkyOptions& o, const atmos::DropShapeSpec& shape, const ProgressFn& progress = {});
// Where the profiles computed (their largest_error) are above the Lee tables' tolerance
// (atmos::kLeeErrorTolerance), a line saying so and naming the sampling that would meet it (the error
// falls about as 1 / sampling) from `sampling`, the one they were computed at (ProfileAccuracy), the
// flag spelled for `door`; nothing otherwise.
std::optional<std::string> sky_profile_note(std::optional<double> error, double sampling, Door door);

}  // namespace hydrolux::scene
