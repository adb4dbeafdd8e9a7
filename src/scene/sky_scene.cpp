#include "hydrolux/scene/sky_scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/memory.hpp"
#include "hydrolux/scene/bow_tables.hpp"

namespace hydrolux::scene {

std::string sky_word(std::string_view name, Door door) {
  if (const auto* f = find_field(sky_params(), name)) return std::string(spelled(f->param, door));
  if (name == "lut" && door != Door::cli) return "hydrolux sky --lut";  // tables from files: the CLI's only
  if (door != Door::cli) return std::string(name);
  std::string flag = "--" + std::string(name);
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

void check_sky_request(const SkyOptions& o, const atmos::DropShapeSpec& shape, bool tables_given,
                       Door door) {
  const SkySettings& s = o.settings;
  const auto word = [&](std::string_view name) { return sky_word(name, door); };
  if (!shape.spherical()) {
    // Non-spherical drops: their bow, which changes along its arc, is computed here for the scene's
    // sun at kShapePositions position angles (Airy theory of the plane section).
    if (tables_given)
      throw Error(fmt::format("{} {}: non-spherical drops' bow changes along its arc and is computed here at {} "
                              "position angles, while {} tables hold one bow for all of it (omit {} or {})",
                              word("shape"), o.shape, kShapePositions, word("lut"), word("lut"), word("shape")));
    if (s.sun_elevation_deg > max_shape_sun_elevation_deg())
      throw Error(fmt::format("{} {}: non-spherical drops' bow is computed for a sun at most {:g} degrees up "
                              "({} {:g}; the bow is below the horizon anyway)",
                              word("shape"), o.shape, max_shape_sun_elevation_deg(), word("sun_elevation_deg"),
                              s.sun_elevation_deg));
    check_shape_radius(shape, s.radius_um);
  }
  // The tables computed here are Mie's, whose size parameter limit caps the radius; given tables
  // (e.g. geometric optics up to 5000 um) cover what they cover.
  if (shape.spherical() && !tables_given && s.radius_um > max_sky_radius_um())
    throw Error(fmt::format("{} {:g} is outside the valid range [{:g}, {:g}] um of the tables computed without {} "
                            "(Mie's size parameter limit at 380 nm); give tables that cover it with {}",
                            word("radius_um"), s.radius_um, atmos::kMinRadiusUm, max_sky_radius_um(), word("lut"),
                            word("lut")));
  check_polarization(s, true, true, door);
  if (s.corona && !tables_given && s.radius_um > kCoronaMaxRadiusUm)
    throw Error(fmt::format("{}: drops of {:g} um ({}) put their corona within 0.2 degrees of the sun, where nothing "
                            "is drawn; coronas come from cloud droplets of 1-{:g} um (try {} 10) or omit {}",
                            word("corona"), s.radius_um, word("radius_um"), kCoronaMaxRadiusUm, word("radius_um"),
                            word("corona")));
}

void refuse_unused_sky_params(const SkyOptions& o, const std::function<bool(std::string_view)>& given,
                              bool tables_given, bool environment_given, Door door) {
  // The rows' declared conditions (sky_params.cpp: only_with, why), checked by the library's usage
  // tracker in the door's spelling; a switch given off is as good as not given. A choice's value, given
  // or not, is the state its word names ("mode=cube-map").
  ParamUse use(door);
  for (const auto& f : sky_params()) {
    const double v = f.get(o);
    if (given(f.param.name) && (f.param.kind != ParamKind::flag || v != 0))
      use.give(f.param, f.param.kind == ParamKind::flag ? std::string() : f.param.value_text(f.value(o), door));
    else
      use.declare(f.param, f.param.kind == ParamKind::choice ? f.param.value_text(f.value(o), door) : std::string());
  }
  if (tables_given) use.hold("lut");
  if (environment_given) use.hold("environment");
  use.report_unused();
}

void check_sky_memory(const SkySettings& s, Door door, double available) {
  const double need = estimated_bytes(s), avail = available >= 0 ? available : double(available_memory_bytes());
  if (need <= avail) return;
  const double cube =
      s.mode == BowMode::cube_map ? kSkyBytesPerCubeTexel * double(s.cube_face_size) * s.cube_face_size : 0;
  const double frame = need - cube - kSkyFixedBytes;
  const double room = avail - kSkyFixedBytes;
  if (cube > frame) {
    const double fits = std::floor(std::sqrt(std::max(0.0, room - frame) / kSkyBytesPerCubeTexel));
    throw Error(fmt::format("{} {}: the frame and its cube map need about {} of memory and {} is available; faces of "
                            "at most {:g} texels fit",
                            sky_word("cube_face_size", door), s.cube_face_size, format_bytes(need),
                            format_bytes(avail), std::max(0.0, fits)));
  }
  const double pixels = double(s.camera.width) * s.camera.height;
  const double fit_pixels = std::max(0.0, room - cube) / kSkyBytesPerPixel;
  const double k = std::sqrt(fit_pixels / pixels);
  const double w = std::floor(s.camera.width * k), h = std::floor(s.camera.height * k);
  const Param& size = sky_param("size");
  const auto size_text = [&](double width, double height) {
    return fmt::format("{} {}", spelled(size, door), size.value_text({width, height}, door));
  };
  throw Error(fmt::format("{}: the frame needs about {} of memory and {} is available; at most about {:.0f} "
                          "megapixels fit ({} at this aspect)",
                          size_text(s.camera.width, s.camera.height), format_bytes(need), format_bytes(avail),
                          fit_pixels / 1e6, size_text(w, h)));
}

std::optional<std::string> sky_profile_note(std::optional<double> error, double sampling, Door door) {
  if (!error || *error <= atmos::kLeeErrorTolerance) return std::nullopt;
  const double need = atmos::sampling_for_tolerance(*error, sampling, sky_param("sampling").hi);
  return fmt::format("the bow profiles' estimated error is {:.2g}% RMS in luminance, more than {:g}%: give {} {:g} "
                     "(the error falls about as 1 / {})",
                     100 * *error, 100 * atmos::kLeeErrorTolerance, sky_word("sampling", door), need,
                     sky_word("sampling", door));
}

SkyTables compute_sky_tables(const SkyOptions& o, const atmos::DropShapeSpec& shape, const ProgressFn& progress) {
  const SkySettings& s = o.settings;
  const bool need_corona = s.corona && s.radius_um <= kCoronaMaxRadiusUm;
  const int jobs = need_corona ? 2 : 1;
  int done = 0;
  const auto sub = [&](double f, std::string_view label) {
    if (progress) progress((done + f) / jobs, label);
  };
  // With a polariser the tables carry the Stokes Q (1.04x the time of I alone, BENCHMARKS.md).
  const bool polarized = s.polarizer_deg.has_value() || s.stokes;
  const auto spec = [&](atmos::LeeTableKind kind) {
    atmos::LeeSpec p = sky_profile_spec(kind, s.radius_um, o.sampling);
    p.stokes = polarized;
    return p;
  };
  SkyTables t;
  if (!shape.spherical())
    t.rainbow = compute_shaped_rainbow(shape, s.radius_um, o.sampling, s.sun_elevation_deg, s.secondary, sub,
                                       polarized);
  else
    t.rainbow = compute_bow_slice(spec(atmos::LeeTableKind::rainbow), sub);
  ++done;
  if (need_corona) t.corona = compute_bow_slice(spec(atmos::LeeTableKind::corona), sub);
  return t;
}

}  // namespace hydrolux::scene
