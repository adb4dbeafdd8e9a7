#include "hydrolux/scene/bow_tables.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "hydrolux/atmos/lee_params.hpp"
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

atmos::LeeSpec sky_profile_spec(atmos::LeeTableKind kind, double radius_um, std::optional<double> sampling) {
  atmos::LeeSpec spec = bow_table_spec(kind, radius_um);
  spec.sampling = sampling.value_or(1);
  spec.sampling_most = sampling ? 0.0 : atmos::kAutoSamplingMost;
  return spec;
}

double max_sky_radius_um() { return atmos::max_radius_um(sky_profile_spec(atmos::LeeTableKind::rainbow, 500, 1)); }

BowSlice compute_bow_slice(const atmos::LeeSpec& profile, const ProgressFn& progress) {
  const atmos::LeeTable t = atmos::compute_lee_table(profile, progress);
  BowSlice s = slice_at_radius(bow_table(t), profile.radius_min_um);
  s.error = t.error.luminance_rms;
  s.sampling = t.spec.sampling;
  s.first_error = t.first_error;
  return s;
}

std::optional<double> largest_error(const RainbowSlices& rainbow, const BowSlice& corona) {
  std::optional<double> e = corona.error;
  for (const BowSlice& s : rainbow.by_position)
    if (s.error) e = std::max(e.value_or(0.0), *s.error);
  return e;
}

ProfileAccuracy profile_accuracy(const RainbowSlices& rainbow, const BowSlice& corona) {
  ProfileAccuracy a;
  a.error = largest_error(rainbow, corona);
  const auto add = [&](const BowSlice& s) {
    a.sampling = std::max(a.sampling, s.sampling);
    if (s.first_error) a.first_error = std::max(a.first_error.value_or(0.0), *s.first_error);
  };
  add(corona);
  for (const BowSlice& s : rainbow.by_position) add(s);
  return a;
}

double max_shape_sun_elevation_deg() { return atmos::lee_param("sun_elevation_deg").hi; }

atmos::LeeSpec shape_table_spec(atmos::LeeSpec base, const atmos::DropShapeSpec& shape, double sun_elevation_deg,
                                double position_deg, int p) {
  base.theory = scatter::Theory{scatter::TheoryKind::Airy, p};
  base.shape = shape;
  base.sun_elevation_deg = sun_elevation_deg;
  base.position_deg = position_deg;
  base.canting_deg = 0;
  return base;
}

atmos::LeeSpec sky_shape_profile_spec(const atmos::DropShapeSpec& shape, double radius_um, std::optional<double> sampling,
                                      double sun_elevation_deg, double position_deg, int p) {
  return shape_table_spec(sky_profile_spec(atmos::LeeTableKind::rainbow, radius_um, sampling), shape,
                          sun_elevation_deg, position_deg, p);
}

double max_sky_radius_um(const atmos::DropShapeSpec& shape) {
  if (shape.spherical()) return max_sky_radius_um();
  // Airy theory's size parameter limit and the shape's (beard-chuang drops flatten with the radius).
  const atmos::LeeSpec spec = sky_shape_profile_spec(shape, 500, 1, 0, 0);
  return std::min(atmos::max_radius_um(spec), atmos::max_shape_radius_um(spec));
}

void check_shape_radius(const atmos::DropShapeSpec& shape, double radius_um) {
  const double rmax = max_sky_radius_um(shape);
  if (radius_um <= rmax) return;
  throw DomainError("radius_um", radius_um, atmos::kMinRadiusUm, rmax,
                    fmt::format("{{shape}} {} drops ({})", atmos::drop_shape_name(shape),
                                shape.kind == atmos::DropShapeSpec::Kind::beard_chuang
                                    ? fmt::format("beyond, the largest drops of the 10% spread are flatter than the "
                                                  "axis ratio {:g} the plane-section method needs: "
                                                  "docs/non-spherical.md",
                                                  atmos::kMinBowAxisRatio)
                                    : std::string("Airy theory's size parameter limit at 380 nm")));
}

RainbowSlices compute_shaped_rainbow(const atmos::DropShapeSpec& shape, double radius_um, std::optional<double> sampling,
                                     double sun_elevation_deg, bool secondary, const ProgressFn& progress,
                                     bool stokes) {
  std::vector<atmos::LeeSpec> specs;
  for (int k = 0; k < kShapePositions; ++k)
    for (int p = 2; p <= (secondary ? 3 : 2); ++p) {
      specs.push_back(sky_shape_profile_spec(shape, radius_um, sampling, sun_elevation_deg, k * kShapePositionStepDeg, p));
      specs.back().stokes = stokes;
      atmos::validate(specs.back());
    }
  RainbowSlices out;
  out.by_position.reserve(kShapePositions);
  const double jobs = double(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    ProgressFn sub;
    if (progress)
      sub = [&, i](double f, std::string_view label) {
        progress((double(i) + f) / jobs,
                 fmt::format("position {:g} deg, {} {}", specs[i].position_deg, specs[i].theory.p == 2 ? "primary" : "secondary", label));
      };
    BowSlice s = compute_bow_slice(specs[i], sub);
    if (specs[i].theory.p == 2) {
      out.by_position.push_back(std::move(s));
    } else {  // the secondary, on the same rows: added; the slice states the larger error and sampling
      BowSlice& sum = out.by_position.back();
      for (std::size_t j = 0; j < sum.rgb.size(); ++j) sum.rgb[j] += s.rgb[j];
      for (std::size_t j = 0; j < sum.q.size(); ++j) sum.q[j] += s.q[j];
      if (s.error) sum.error = std::max(sum.error.value_or(0.0), *s.error);
      sum.sampling = std::max(sum.sampling, s.sampling);
      if (s.first_error) sum.first_error = std::max(sum.first_error.value_or(0.0), *s.first_error);
    }
  }
  return out;
}

atmos::LeeSpec shaped_table_spec(const atmos::LeeSpec& rainbow, const atmos::DropShapeSpec& shape,
                                 double sun_elevation_deg) {
  atmos::LeeSpec spec = shape_table_spec(rainbow, shape, sun_elevation_deg, 0, 2);
  spec.columns = std::min(spec.columns, kShapedTableMaxColumns);
  return spec;
}

ShapedRainbowTable compute_shaped_rainbow_table(const atmos::LeeSpec& rainbow, const atmos::DropShapeSpec& shape,
                                                double sun_elevation_deg, const ProgressFn& progress) {
  if (shape.spherical())
    throw Error("the position-dependent rainbow table is for non-spherical drops (spheres' bow is the same all round)");
  const atmos::LeeSpec first = shaped_table_spec(rainbow, shape, sun_elevation_deg);
  if (first.rows > kShapedTableMaxRows)
    throw Error(fmt::format("the position-dependent rainbow table has at most {} rows (a 3-D texture's side); {} asked",
                            kShapedTableMaxRows, first.rows));
  std::vector<atmos::LeeSpec> specs;
  for (int k = 0; k < kShapePositions; ++k)
    for (int p = 2; p <= 3; ++p) {
      atmos::LeeSpec s = first;
      s.position_deg = k * kShapePositionStepDeg;
      s.theory.p = p;
      atmos::validate(s);
      specs.push_back(s);
    }
  ShapedRainbowTable out;
  out.shape = shape;
  out.sun_elevation_deg = sun_elevation_deg;
  const double jobs = double(specs.size());
  std::size_t layer = 0;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    ProgressFn sub;
    if (progress)
      sub = [&, i](double f, std::string_view label) {
        progress((double(i) + f) / jobs, fmt::format("position {:g} deg, {} {}", specs[i].position_deg,
                                                      specs[i].theory.p == 2 ? "primary" : "secondary", label));
      };
    atmos::LeeTable t = atmos::compute_lee_table(specs[i], sub);
    const BowTable b = bow_table(t);  // the gamut-mapped RGB as float, as the compositor's slices hold it
    const double error = t.error.luminance_rms.value_or(0.0), sampling = t.spec.sampling;
    if (i == 0) {
      out.first = std::move(t);
      out.rgb.assign(std::size_t(kShapePositions) * b.rgb.size(), 0.f);
      out.q.assign(b.has_q() ? out.rgb.size() : 0, 0.f);
    }
    if (specs[i].theory.p == 2) {
      layer = out.position_deg.size();
      out.position_deg.push_back(specs[i].position_deg);
      out.error_by_layer.push_back(error);
      out.sampling_by_layer.push_back(sampling);
    } else {
      out.error_by_layer[layer] = std::max(out.error_by_layer[layer], error);
      out.sampling_by_layer[layer] = std::max(out.sampling_by_layer[layer], sampling);
    }
    // The secondary added to its position's primary, in float, as compute_shaped_rainbow does.
    float* dst = &out.rgb[layer * b.rgb.size()];
    for (std::size_t j = 0; j < b.rgb.size(); ++j) dst[j] += b.rgb[j];
    if (!out.q.empty()) {
      float* dq = &out.q[layer * b.q.size()];
      for (std::size_t j = 0; j < b.q.size(); ++j) dq[j] += b.q[j];
    }
  }
  return out;
}

}  // namespace hydrolux::scene
