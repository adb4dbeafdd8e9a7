#include "hydrolux/scene/bow_tables.hpp"

#include <fmt/format.h>

#include "hydrolux/core/error.hpp"

namespace hydrolux::scene {

atmos::LeeSpec bow_table_spec(atmos::LeeTableKind kind, std::optional<double> radius_um, int rows) {
  if (kind != atmos::LeeTableKind::rainbow && kind != atmos::LeeTableKind::corona)
    throw Error(
        fmt::format("a scene draws from rainbow and corona tables, not a {} table", atmos::table_kind_name(kind)));
  atmos::LeeSpec s = atmos::default_lee_spec(kind);
  if (kind == atmos::LeeTableKind::corona) {
    s.angle_max_deg = kCoronaTableMaxDeg;
    s.rows = 2 * rows;
  } else {
    s.rows = rows;
  }
  if (radius_um) {
    s.radius_min_um = s.radius_max_um = *radius_um;
    s.columns = 1;
  }
  return s;
}

atmos::LeeSpec sky_profile_spec(atmos::LeeTableKind kind, double radius_um, double sampling) {
  atmos::LeeSpec spec = bow_table_spec(kind, radius_um);
  spec.sampling = sampling;
  return spec;
}

double max_sky_radius_um() { return atmos::max_radius_um(sky_profile_spec(atmos::LeeTableKind::rainbow, 500, 1)); }

BowSlice compute_bow_slice(const atmos::LeeSpec& profile, const ProgressFn& progress) {
  return slice_at_radius(bow_table(atmos::compute_lee_table(profile, progress)), profile.radius_min_um);
}

}  // namespace hydrolux::scene
