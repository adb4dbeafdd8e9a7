#pragma once
// The Lee tables a rainbow scene draws from: one definition of their spans for every door that
// computes them (hydrolux sky without --lut, hydrolux export, the gallery's sky scenes, the sky
// benchmark). The rainbow table spans the bow side, 90-180 degrees, in kBowTableRows rows (0.088
// degree); the corona table the whole forward hemisphere, 0-90 degrees, in twice as many rows
// (0.044 degree: four rows to the closest rings of 50 um droplets), so that with the corona on, the
// light small drops scatter forward has no edge at the corona's usual 20 degrees (hydrolux lee
// --table corona's default). Otherwise each is its kind's default (atmos::default_lee_spec): the
// rainbow of 5-800 um drops, the corona of 1-50 um droplets, a 10% gamma spread, Mie theory.
#include <optional>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/progress.hpp"
#include "hydrolux/scene/compositor.hpp"

namespace hydrolux::scene {

inline constexpr int kBowTableRows = 1024;
inline constexpr double kCoronaTableMaxDeg = 90;
// Coronas come from cloud droplets: the corona table's largest radius (drops above it put their
// corona within 0.2 degrees of the sun, where nothing is drawn).
inline constexpr double kCoronaMaxRadiusUm = 50;

// The table of `kind` (rainbow or corona; Error for a glory): with `radius_um`, one column of drops
// of that number-mean radius (a profile, the spread kept), else the kind's radii; `rows` rows for
// the rainbow and twice as many for the corona. Not validated (atmos::validate).
atmos::LeeSpec bow_table_spec(atmos::LeeTableKind kind, std::optional<double> radius_um = std::nullopt,
                              int rows = kBowTableRows);

// The tables hydrolux sky computes for one radius without given tables: bow_table_spec's profile at
// `radius_um` with the sampling multiplier `sampling`. Not validated.
atmos::LeeSpec sky_profile_spec(atmos::LeeTableKind kind, double radius_um, double sampling);
// The largest radius those tables allow (atmos::max_radius_um of the rainbow's: Mie's size parameter
// limit at 380 nm for the 10% spread), so that the help, the check and the work agree.
double max_sky_radius_um();

// A profile's table (one column) computed and sliced at its radius, for the compositor.
BowSlice compute_bow_slice(const atmos::LeeSpec& profile, const ProgressFn& progress = {});

}  // namespace hydrolux::scene
