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
#include <vector>

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
// `radius_um` with the sampling multiplier `sampling`; unset, automatic (atmos::LeeSpec::sampling_most:
// 1, and once more at up to atmos::kAutoSamplingMost where the profile's estimated error is above 1%).
// Not validated.
atmos::LeeSpec sky_profile_spec(atmos::LeeTableKind kind, double radius_um, std::optional<double> sampling);
// The largest radius those tables allow (atmos::max_radius_um of the rainbow's: Mie's size parameter
// limit at 380 nm for the 10% spread), so that the help, the check and the work agree.
double max_sky_radius_um();

// A profile's table (one column) computed and sliced at its radius, for the compositor, with the
// table's estimated error and sampling (BowSlice::error, sampling, first_error).
BowSlice compute_bow_slice(const atmos::LeeSpec& profile, const ProgressFn& progress = {});
// The largest estimated error (BowSlice::error) of the slices that state one: what `hydrolux sky` and
// hydrolux.sky report of the profiles they computed.
std::optional<double> largest_error(const RainbowSlices& rainbow, const BowSlice& corona);
// What the profiles computed for a scene say of their accuracy: the largest estimated error
// (largest_error), the largest sampling multiplier they were computed at, and, where automatic
// sampling computed some a second time, the largest first-pass estimate among those.
struct ProfileAccuracy {
  std::optional<double> error;
  double sampling = 0;
  std::optional<double> first_error;
};
ProfileAccuracy profile_accuracy(const RainbowSlices& rainbow, const BowSlice& corona);

// ---- non-spherical drops (hydrolux sky --shape; docs/sky.md, "Drop shapes") ----
//
// Their bow changes along its arc (docs/non-spherical.md): the scene computes it at
// kShapePositions position angles 0, 10, ..., 180 degrees and the compositor interpolates
// linearly between the two nearest (RainbowSlices).
inline constexpr int kShapePositions = 19;
inline constexpr double kShapePositionStepDeg = 180.0 / (kShapePositions - 1);
// The largest sun elevation the non-spherical tables take (atmos::lee_param("sun_elevation_deg")).
double max_shape_sun_elevation_deg();

// The rainbow table `base` (its radii, rows, spread and sampling) for `shape` drops at one position
// angle: Airy theory of the drops' plane section, order `p` (2 the primary, 3 the secondary), with
// the sun's elevation and the position angle; the drops' axes vertical (no canting). Not validated.
atmos::LeeSpec shape_table_spec(atmos::LeeSpec base, const atmos::DropShapeSpec& shape, double sun_elevation_deg,
                                double position_deg, int p = 2);
// The rainbow profile of `shape` drops at one position angle: sky_profile_spec's rainbow profile
// (the radius, its 10% spread, the rows, `sampling`, unset for automatic) in Airy theory of the drops' plane section,
// order `p` (2 the primary, 3 the secondary), with the sun's elevation and the position angle; the
// drops' axes vertical (no canting). Not validated.
atmos::LeeSpec sky_shape_profile_spec(const atmos::DropShapeSpec& shape, double radius_um, std::optional<double> sampling,
                                      double sun_elevation_deg, double position_deg, int p = 2);
// The largest radius those profiles allow (whole micrometres): Airy theory's size parameter limit,
// and for beard-chuang the flattest drop of the spread keeping an axis ratio of at least
// atmos::kMinBowAxisRatio (about 1.1 mm). For spheres, max_sky_radius_um().
double max_sky_radius_um(const atmos::DropShapeSpec& shape);
// DomainError ("radius_um"; its range "of shape <name> drops (why)") when radius_um exceeds max_sky_radius_um(shape):
// the one check hydrolux sky and hydrolux export make before computing the shaped profiles.
void check_shape_radius(const atmos::DropShapeSpec& shape, double radius_um);

// The rainbow of `shape` drops of `radius_um` for a sun `sun_elevation_deg` up: the profiles at the
// kShapePositions position angles, the primary (airy) and, when `secondary`, the secondary (airy:3)
// added, each sliced at the radius (the slice's error and sampling the larger of the two orders').
// `sampling` unset: automatic, per table (sky_profile_spec). Validates each spec (atmos::validate).
// `progress` rises from 0 to 1 over all of them. `stokes`: the slices carry the Stokes Q too (for a
// polariser).
RainbowSlices compute_shaped_rainbow(const atmos::DropShapeSpec& shape, double radius_um, std::optional<double> sampling,
                                     double sun_elevation_deg, bool secondary, const ProgressFn& progress = {},
                                     bool stokes = false);

// ---- the non-spherical drops' table for engines (hydrolux export --shape; docs/sky.md) ----
//
// A 3-D table: the rainbow of `shape` drops over radius (columns), scattering angle (rows) and
// position angle (kShapePositions layers, 0, 10, ..., 180 degrees), for one sun elevation; the
// primary and the secondary added, as compute_shaped_rainbow adds them. A shader reads it as a 3-D
// texture (data/shaders/README.md).
//
// At most kShapedTableMaxColumns radius columns (the table is kShapePositions times a 2-D one: 128
// x 1024 x 19 x RGB float32 is 30 MB) and kShapedTableMaxRows rows (the side of a 3-D texture
// Direct3D 11 guarantees; WebGL 2 guarantees only 256, most implementations 2048).
inline constexpr int kShapedTableMaxColumns = 128;
inline constexpr int kShapedTableMaxRows = 2048;

struct ShapedRainbowTable {
  atmos::DropShapeSpec shape;
  double sun_elevation_deg = 0;
  std::vector<double> position_deg;  // per layer: 180 k / (kShapePositions - 1)
  // The primary's table at position 0: its spec (radii, rows, axis, sampling, spectrum), axes and
  // colour metadata, shared by every layer (the values of the layers are in `rgb`).
  atmos::LeeTable first;
  // positions x rows x columns x 3 (linear RGB, gamut-mapped per order as the Lee tables' RGB, sr^-1):
  // value (layer k, row j, column i, channel c) at ((k * rows + j) * columns + i) * 3 + c.
  std::vector<float> rgb;
  // The same of the Stokes Q (BowTable::q) when `rainbow` asked for it (LeeSpec::stokes); else empty.
  std::vector<float> q;
  // Per layer, the larger of its two orders' estimated error (LeeTable::error's luminance_rms) and
  // sampling multiplier: with automatic sampling each order's table at each position chooses its own.
  std::vector<double> error_by_layer, sampling_by_layer;
  int columns() const { return first.columns(); }
  int rows() const { return first.rows(); }
  int positions() const { return int(position_deg.size()); }
};

// The spec of the 3-D table's layers for the rainbow table `rainbow` (hydrolux export's): its radii
// and rows, its columns capped at kShapedTableMaxColumns, the shape's primary at position 0 (the
// other layers and orders differ in position_deg and theory only). Not validated.
atmos::LeeSpec shaped_table_spec(const atmos::LeeSpec& rainbow, const atmos::DropShapeSpec& shape,
                                 double sun_elevation_deg);
// Computes it: for each of the kShapePositions positions, the primary (airy) and the secondary
// (airy:3) tables of shaped_table_spec, added. Validates each spec (atmos::validate); Error for a
// spherical shape or more than kShapedTableMaxRows rows. `progress` rises from 0 to 1.
ShapedRainbowTable compute_shaped_rainbow_table(const atmos::LeeSpec& rainbow, const atmos::DropShapeSpec& shape,
                                                double sun_elevation_deg, const ProgressFn& progress = {});

}  // namespace hydrolux::scene
