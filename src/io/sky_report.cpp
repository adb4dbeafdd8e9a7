#include "hydrolux/io/sky_report.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/scene/compositor.hpp"
#include "hydrolux/scene/sky_model.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::io {

nlohmann::json sky_parameters_json(double turbidity) {
  nlohmann::json j;
  j["format"] = "hydrolux-sky-parameters";
  j["format_version"] = 1;
  j["hydrolux_version"] = kVersion;
  j["model"] =
      "Preetham, Shirley and Smits 1999 sky; the sun is ASTM G173 direct (air mass 1.5) carried to the air mass "
      "of Kasten and Young 1989 with Preetham's Rayleigh and aerosol optical depths; docs/sky.md";
  j["units"] = {{"radiance", "cd/m^2 per channel, linear Rec.709 (luminance 0.2126 R + 0.7152 G + 0.0722 B)"},
                {"irradiance", "lux per channel"},
                {"zenith_Y_kcd", "kcd/m^2"}};
  j["turbidity"] = turbidity;
  j["camera_height_m"] = scene::kCameraHeightM;
  j["sun_angular_radius_deg"] = scene::kSunAngularRadiusDeg;
  j["ground_albedo"] = {scene::kGroundAlbedo[0], scene::kGroundAlbedo[1], scene::kGroundAlbedo[2]};
  j["extinction_efficiency"] = 2.0;
  // beta_geo = pi M2 of Marshall-Palmer rain is a power law in the rain rate: c R^0.63.
  const double b1 = scene::rain_beta_geo_per_m(1.0), b10 = scene::rain_beta_geo_per_m(10.0);
  j["rain"] = {{"beta_geo_per_m", "coefficient * rain_rate_mmh ^ exponent (Marshall and Palmer 1948, n0 = 1.6e7 m^-4 "
                                  "per metre of radius, Lambda = 8200 R^-0.21 m^-1)"},
               {"coefficient", b1},
               {"exponent", std::log10(b10 / b1)}};
  j["tone_map"] = {{"exposure", 0.6}, {"white", 6.0},
                   {"formula", "x = exposure L / l_ref; x (1 + x / white^2) / (1 + x), clamped to [0,1]; sRGB"}};
  // The sky's polarisation, for a linear polariser in front of the camera (scene::sky_dolp).
  j["polarization"] = {
      {"sky_max_dolp", scene::kSkyMaxDolpDefault},
      {"sky_model",
       "Rayleigh single scattering with depolarisation: the sky (above the horizon, off the sun's disk) is polarised "
       "normal to the scattering plane with degree P(gamma) = P90 (1 - cos^2 gamma) / (P90 (1 + cos^2 gamma) + 1 - "
       "P90), cos gamma = dot(view, sun), P90 = sky_max_dolp (0.946 for air's molecules alone, 0.6-0.85 measured in "
       "clear skies); the sun's disk, the ground and the scene are unpolarised"},
      {"polarizer",
       "axis angle A in the image, from its horizontal towards its up: with d the view ray, s the sun, r the "
       "camera's right, e = d x s, h = r - (r.d) d, v = d x h, ea = cos A (e.h) + sin A (e.v), c2 = clamp(2 ea^2 / "
       "((e.e) (h.h)) - 1, -1, 1) (0 where e.e or h.h < 1e-12); the background passes bg (1 + P c2) / 2 (P = 0 "
       "where unpolarised); the rain's T passes max((T + T_Q c2) / 2, 0), T_Q the same lookups in the Q tables "
       "(*_q.f32)"},
      {"tone_map", "with a polariser l_ref / 2 in the tone map (a camera opens up one stop for the light it "
                   "halves); the whitepaper blend keeps l_ref"}};
  // One column per quantity, a value per sun elevation from 0 to 90 degrees.
  const auto rgb = [](const Vec3& v) { return nlohmann::json{v.x, v.y, v.z}; };
  const auto coef = [](const scene::Perez& p) { return nlohmann::json{p.A, p.B, p.C, p.D, p.E}; };
  scene::SunSky first;
  for (int deg = 0; deg <= 90; ++deg) {
    const scene::SunSky s = scene::make_sun_sky(deg, turbidity);
    if (deg == 0) first = s;
    const std::pair<const char*, nlohmann::json> row[] = {
        {"elevations_deg", deg},
        {"sun_illuminance_lux", s.sun_illuminance_lux},
        {"sun_rgb", rgb(s.sun_rgb)},
        {"sky_illuminance_rgb", rgb(s.sky_illuminance_rgb)},
        {"ground_rgb", rgb(s.ground_rgb)},
        {"l_ref", s.l_ref},
        {"zenith_Y_kcd", s.zenith_Y_kcd},
        {"zenith_x", s.zenith_x},
        {"zenith_y", s.zenith_y},
        {"perez_Y", coef(s.perez[0])},
        {"perez_x", coef(s.perez[1])},
        {"perez_y", coef(s.perez[2])},
        {"perez_at_sun", {s.perez_at_sun[0], s.perez_at_sun[1], s.perez_at_sun[2]}}};
    for (const auto& [key, value] : row) j[key].push_back(value);
  }
  j["xyz_to_rgb"] = {{first.xyz_to_rgb[0][0], first.xyz_to_rgb[0][1], first.xyz_to_rgb[0][2]},
                     {first.xyz_to_rgb[1][0], first.xyz_to_rgb[1][1], first.xyz_to_rgb[1][2]},
                     {first.xyz_to_rgb[2][0], first.xyz_to_rgb[2][1], first.xyz_to_rgb[2][2]}};
  return j;
}

nlohmann::json write_shaped_rainbow_table(OutputDirectory& dir, const std::string& name,
                                          const scene::ShapedRainbowTable& t) {
  static_assert(std::endian::native == std::endian::little, "the .f32 tables are little-endian");
  const atmos::LeeTable& f = t.first;
  // The Lee table sidecar's description of the radii, the rows, the spectrum and the colours (shared
  // by every layer), without what belongs to a 2-D table's images.
  nlohmann::json j = io::lee_sidecar(f, atmos::lee_images(f), "", "");
  for (const char* k : {"files", "png", "work", "channels"}) j.erase(k);
  j["format"] = "hydrolux-lee-table-3d";
  j["format_version"] = 1;
  j["theory"] = "airy + airy:3";
  j["orders"] = "the primary (Airy theory of the plane section, p = 2) and the secondary (p = 3), each gamut-mapped "
                "as a Lee table's RGB, then added: without the secondary, apply w(theta) = smoothstep(132, 136, "
                "theta) as for the spheres' table";
  j["files"] = {{"f32", name + ".f32"}};
  j["width"] = t.columns();
  j["height"] = t.rows();
  j["depth"] = t.positions();
  j["position_deg"] = io::to_json(t.position_deg);
  j["sun_elevation_deg"] = t.sun_elevation_deg;
  j["drop_shape"].erase("position_deg");  // one per layer: position_deg
  // Each layer's tables chose their own sampling (automatic sampling) and state their own error: the
  // sidecar the largest of them, and each layer's (the larger of its two orders').
  const auto largest = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  j["sampling"]["multiplier"] = largest(t.sampling_by_layer);
  j["sampling"]["by_layer"] = io::to_json(t.sampling_by_layer);
  j["sampling"].erase("first_pass");
  j["error"]["luminance_rms"] = largest(t.error_by_layer);
  j["error"]["luminance_rms_by_layer"] = io::to_json(t.error_by_layer);
  j["error"].erase("q_rms");  // the first layer's alone
  j["layout"]["z"] =
      "position angle: layer k holds position_deg[k] (0, 10, ..., 180), the angle around the antisolar point a = "
      "-sun from the zenith side (0, the bow's top) to the nadir side (180, its bottom), the same left and right: "
      "u0 = normalize(up - dot(up, a) a), u90 = normalize(cross(a, u0)), psi = atan2(|dot(v, u90)|, dot(v, u0)); "
      "interpolate linearly between the two nearest layers";
  j["layout"]["sample"] =
      "texel (i, j, k) is centred on radius_um[i], its row's angle and position_deg[k]; as a Lee table's pixel it is "
      "averaged over the sun's disk and its row's cell; each column is one size distribution";
  j["f32_layout"] =
      "little-endian float32, depth x height x width x 3 (positions x rows x columns x R, G, B): value (layer k, row "
      "j, column i, channel c) at index ((k * height + j) * width + i) * 3 + c; a 3-D texture of width x height x "
      "depth texels";
  j["channels"] = {{"R,G,B", "linear RGB, gamut-mapped as the Lee tables' (per order, then added)"}};
  const bool with_q = !t.q.empty();
  if (with_q) {
    j["files"]["f32_q"] = name + "_q.f32";
    j["channels"]["Q"] =
        "the Stokes Q (see stokes) in f32's layout as linear RGB: each order's Q XYZ through color_space.xyz_to_rgb, "
        "not gamut-mapped (signed: > 0 polarised normal to the scattering plane, tangential to the bow), then added";
  }
  const auto raw = [](const std::vector<float>& v) {
    std::string bytes(v.size() * sizeof(float), '\0');
    std::memcpy(bytes.data(), v.data(), bytes.size());
    return bytes;
  };
  dir.write(name + ".f32", raw(t.rgb));
  if (with_q) dir.write(name + "_q.f32", raw(t.q));
  dir.write(name + ".json", j.dump(1) + "\n");
  nlohmann::json files = {name + ".f32", name + ".json"};
  if (with_q) files.push_back(name + "_q.f32");
  nlohmann::json entry = {{"kind", atmos::table_kind_name(f.spec.table)},
          {"shape", atmos::drop_shape_name(t.shape)},
          {"sun_elevation_deg", t.sun_elevation_deg},
          {"columns", t.columns()},
          {"rows", t.rows()},
          {"positions", t.positions()},
          {"radius_um", {f.radius_um.front(), f.radius_um.back()}},
          {"angle_deg", {f.angle_deg.front(), f.angle_deg.back()}},
          {"position_deg", {t.position_deg.front(), t.position_deg.back()}},
          {"files", files}};
  if (with_q) entry["stokes_q"] = name + "_q.f32";
  return entry;
}

nlohmann::json write_engine_shaders(OutputDirectory& dir) {
  nlohmann::json names = nlohmann::json::array();
  for (const auto& f : detail::embedded_files()) {
    const std::string_view p = f.path;
    if (p.rfind("shaders/", 0) != 0) continue;
    const std::string rest(p.substr(8));
    if (rest.rfind("glsl/", 0) != 0 && rest.rfind("hlsl/", 0) != 0 && rest.find('/') != std::string::npos) continue;
    dir.write(rest, f.text);
    names.push_back(rest);
  }
  return names;
}

}  // namespace hydrolux::io
