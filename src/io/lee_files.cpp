// The files of a Lee table: see hydrolux/io/lee_files.hpp.
#include "hydrolux/io/lee_files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::io {

nlohmann::json to_json(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(x);
  return a;
}

namespace {

// The drops' shape and, for non-spherical drops, the bow's point and each column's axis ratio.
nlohmann::json drop_shape_json(const atmos::LeeTable& t) {
  const auto& s = t.spec;
  nlohmann::json j{{"name", atmos::drop_shape_name(s.shape)}};
  if (s.shape.spherical()) return j;
  j["method"] = "Airy theory of the plane section (docs/non-spherical.md)";
  j["sun_elevation_deg"] = s.sun_elevation_deg;
  j["position_deg"] = s.position_deg;
  j["canting_deg"] = s.canting_deg;
  nlohmann::json q = nlohmann::json::array();
  for (double r : t.radius_um) q.push_back(atmos::drop_axis_ratio(s.shape, r));
  j["axis_ratio"] = q;
  j["axis_ratio_of"] = "the drop of each column's radius_um (polar over equatorial axis)";
  return j;
}

// The Stokes Q's basis and sign (atmos::LeeTable::q_xyz).
nlohmann::json stokes_json() {
  return {{"basis", "the scattering plane (sun, drop, observer): Q = (|S1|^2 - |S2|^2) / 2 in the normalisation of "
                    "I = (|S1|^2 + |S2|^2) / 2, S1 perpendicular and S2 parallel to that plane (Bohren & Huffman); "
                    "integrated exactly as I (spectrum x CIE observer, sizes, the sun's disk); U = 0 and V = 0 in "
                    "this basis"},
          {"sign", "Q > 0: polarised perpendicular to the scattering plane, i.e. tangential to the bow (a "
                   "rainbow's usual state); Q < 0: radial"},
          {"dolp", "Q_Y / I_Y: the luminance-weighted degree of linear polarisation, signed as Q"}};
}

// What the table cannot resolve (atmos::lee_resolution_notes), in the library's names.
nlohmann::json notes_json(const atmos::LeeTable& t) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& n : t.notes) a.push_back(spell_quantities(n, {}));
  return a;
}
std::string notes_text(const atmos::LeeTable& t) {
  std::string s;
  for (const auto& n : t.notes) s += (s.empty() ? "" : "; ") + spell_quantities(n, {});
  return s;
}

// The table's estimated error (atmos::LeeError), relative RMS over the table; null with one wavelength.
nlohmann::json error_json(const atmos::LeeTable& t) {
  const auto value = [](const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); };
  nlohmann::json e = {{"luminance_rms", value(t.error.luminance_rms)}};
  if (t.spec.stokes) e["q_rms"] = value(t.error.q_rms);
  e["method"] = "the table of the even-numbered wavelengths against the odd-numbered, each scaled to the whole: "
                "half their difference per pixel, its root mean square over the table relative to that of the "
                "luminance Y (Q's too, relative to I's luminance); an estimate of the sampling's error (docs/lee.md)";
  return e;
}

}  // namespace

nlohmann::json lee_profile_json(const atmos::LeeTable& t) {
  nlohmann::json j;
  j["radius_um"] = t.radius_um.front();
  j["notes"] = notes_json(t);
  j["error"] = error_json(t);
  j["theory"] = scatter::theory_name(t.spec.theory);
  j["drop_shape"] = drop_shape_json(t);
  j["units"] = "sr^-1";
  j["color_space"] = color::rgb_space_name(t.spec.rgb_space);
  j["angle_deg"] = to_json(t.angle_deg);
  nlohmann::json rgb = nlohmann::json::array(), lum = nlohmann::json::array(), xyz = nlohmann::json::array();
  for (int r = 0; r < t.rows(); ++r) {
    const auto v = t.rgb(r, 0);
    rgb.push_back({v[0], v[1], v[2]});
    const auto c = t.at(r, 0);
    xyz.push_back({c.X, c.Y, c.Z});
    lum.push_back(c.Y);
  }
  j["rgb"] = rgb;
  j["luminance"] = lum;
  j["xyz"] = xyz;
  if (t.spec.stokes) {
    nlohmann::json q = nlohmann::json::array(), dolp = nlohmann::json::array();
    for (int r = 0; r < t.rows(); ++r) {
      const auto c = t.q_at(r, 0);
      q.push_back({c.X, c.Y, c.Z});
      dolp.push_back(t.dolp(r, 0));
    }
    j["stokes"] = stokes_json();
    j["q_xyz"] = q;
    j["dolp"] = dolp;
  }
  return j;
}

nlohmann::json lee_sidecar(const atmos::LeeTable& t, const atmos::LeeImages& im, const std::string& exr_name,
                           const std::string& png_name) {
  const auto& s = t.spec;
  nlohmann::json j;
  j["format"] = "hydrolux-lee-table";
  j["format_version"] = 1;
  j["hydrolux_version"] = kVersion;
  j["table"] = atmos::table_kind_name(s.table);
  j["theory"] = scatter::theory_name(s.theory);
  j["notes"] = notes_json(t);
  j["error"] = error_json(t);
  j["quantity"] =
      "T = <dsigma_sca/dOmega> / <pi a^2>: radiance scattered once per unit incident irradiance per unit "
      "projected-area optical depth of the drops (L = E_sun * tau_geo * T; tau_geo = path * sum pi a^2 n(a), "
      "= tau_ext / 2 for drops much larger than the wavelength); averaged over the size distribution, the sun's "
      "disk and the spectrum; not normalised per column";
  j["units"] = "sr^-1";
  j["files"] = {{"exr", exr_name}, {"png", png_name}};
  j["width"] = t.columns();
  j["height"] = t.rows();
  j["layout"] = {
      {"x", "radius: column i holds radius_um[i], increasing to the right"},
      {"y", s.axis == atmos::AngleAxis::angle ? "scattering angle: row j holds angle_deg[j], increasing downward"
                                              : "cosine of the scattering angle: row j holds cos_angle[j], increasing "
                                                "downward (cos_angle = dot(view ray, direction to the sun))"},
      {"sample", "pixel (i, j) is centred on radius_um[i] and its row's angle (sample texel centres: u = (i + 0.5) "
                 "/ width, v = (j + 0.5) / height); its value is averaged over the sun's disk and over its row's "
                 "cell, one row spacing wide along the y axis (a box filter, so fringes finer than the table average "
                 "out instead of aliasing); each column is one size distribution"},
      {"scattering_angle", "0 = forward (looking toward the sun through the drops), 180 = the antisolar point"}};
  j["axis"] = atmos::angle_axis_name(s.axis);
  j["radius_scale"] = atmos::radius_scale_name(s.radius_scale);
  j["radius_um"] = to_json(t.radius_um);
  if (s.axis == atmos::AngleAxis::angle)
    j["angle_deg"] = to_json(t.angle_deg);
  else
    j["cos_angle"] = to_json(t.cos_angle);
  j["channels"] = {
      {"exr", {"R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"}},
      {"R,G,B", "linear RGB, desaturated into the gamut toward the white point at constant luminance"},
      {"XYZ", "CIE 1931 X, Y, Z, unmapped, relative to the sun's luminance (Y = luminance in sr^-1)"}};
  if (s.stokes) {
    j["channels"]["exr"] = {"R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z", "Q.X", "Q.Y", "Q.Z"};
    j["channels"]["Q"] = "the Stokes Q weighted as XYZ (x_bar, y_bar, z_bar), signed, sr^-1: Q.Y / XYZ.Y is the "
                         "luminance-weighted degree of linear polarisation (see stokes)";
    j["stokes"] = stokes_json();
  }
  j["color_space"] = {
      {"rgb", color::rgb_space_name(s.rgb_space)},
      {"white", "D65"},
      {"adaptation", "Bradford, from the sun's white (sun_white_xyz) to D65: sunlight itself is RGB (1,1,1) x "
                     "its luminance"},
      {"gamut_mapping", "a colour with a negative component becomes Y (1,1,1) + s (rgb - Y (1,1,1)) with the "
                        "largest s in [0,1] that makes it non-negative (constant luminance Y)"},
      {"sun_white_xyz", {t.sun_white.X, t.sun_white.Y, t.sun_white.Z}},
      {"xyz_to_rgb", {{t.xyz_to_rgb[0][0], t.xyz_to_rgb[0][1], t.xyz_to_rgb[0][2]},
                      {t.xyz_to_rgb[1][0], t.xyz_to_rgb[1][1], t.xyz_to_rgb[1][2]},
                      {t.xyz_to_rgb[2][0], t.xyz_to_rgb[2][1], t.xyz_to_rgb[2][2]}}}};
  j["spectrum"] = {{"observer", "CIE 1931 2-degree"},
                   {"sun", s.sun.name()},
                   {"wavelength_min_nm", s.wavelength_min_nm},
                   {"wavelength_max_nm", s.wavelength_max_nm},
                   {"wavelengths_nm", to_json(t.wavelengths_nm)}};
  j["sun_disk"] = {{"diameter_deg", s.sun_disk_deg}, {"limb_darkening", s.limb_darkening}};
  if (s.limb_darkening) j["sun_disk"]["limb_darkening_u"] = atmos::kLimbDarkeningU;
  j["size_distribution"] = s.size_spread > 0
                               ? nlohmann::json{{"kind", "gamma"},
                                                {"radius", "number-weighted mean radius"},
                                                {"relative_width", s.size_spread}}
                               : nlohmann::json{{"kind", "monodisperse"}};
  j["drop_shape"] = drop_shape_json(t);
  j["medium"] = {{"drop", s.drop_medium}, {"surrounding", s.surrounding_medium}};
  if (s.temperature_c) j["medium"]["temperature_c"] = *s.temperature_c;
  j["sampling"] = {{"multiplier", s.sampling},
                   {"automatic", s.sampling_most > 0},
                   {"wavelengths", t.work.wavelengths},
                   {"radius_nodes", t.work.radius_nodes},
                   {"angle_cells", t.work.cells},
                   {"seed", s.seed}};
  if (t.first_sampling && t.first_error)
    j["sampling"]["first_pass"] = {{"multiplier", *t.first_sampling}, {"luminance_rms", *t.first_error}};
  j["work"] = {{"evaluations", t.work.evaluations}, {"terms", t.work.terms}, {"term_angles", t.work.term_angles}};
  j["png"] = {{"tone_mapping", "Reinhard et al. 2002 photographic operator on luminance, hue kept: exposure = 0.18 / "
                               "log-average luminance; L' = L (1 + L/white^2) / (1 + L), white = 99.9th percentile "
                               "of the exposed luminance; clipped to [0,1]; sRGB curve; 8 bits"},
              {"exposure", im.exposure},
              {"white", im.white}};
  return j;
}

Dataset lee_dataset(const atmos::LeeTable& t, const atmos::LeeImages& im, std::string_view history) {
  const auto& s = t.spec;
  const std::size_t rows = std::size_t(t.rows()), cols = std::size_t(t.columns()), n = rows * cols;
  Dataset ds;
  const std::string angle = ds.dim("scattering_angle", rows), radius = ds.dim("radius", cols),
                    wavelength = ds.dim("wavelength", t.wavelengths_nm.size()), channel = ds.dim("channel", 3),
                    component = ds.dim("xyz_component", 3);
  ds.add(angle, {angle}, t.angle_deg)
      .attrs.text("units", "degree")
      .text("long_name", "scattering angle (0 forward, looking toward the sun through the drops; 180 the antisolar "
                         "point)");
  ds.add(radius, {radius}, t.radius_um)
      .attrs.text("units", "um")
      .text("long_name", s.size_spread > 0 ? "number-weighted mean drop radius (gamma size distribution)"
                                           : "drop radius");
  ds.add(wavelength, {wavelength}, t.wavelengths_nm)
      .attrs.text("units", "nm")
      .text("standard_name", "radiation_wavelength")
      .text("long_name", "vacuum wavelengths sampled");
  ds.add(channel, {channel}, std::vector<std::string>{"R", "G", "B"})
      .attrs.text("long_name",
                  fmt::format("linear RGB channel ({} primaries, D65 white)", color::rgb_space_name(s.rgb_space)));
  ds.add(component, {component}, std::vector<std::string>{"X", "Y", "Z"})
      .attrs.text("long_name", "CIE 1931 tristimulus component (2-degree observer)");
  std::string coordinates = "cos_scattering_angle";
  ds.add("cos_scattering_angle", {angle}, t.cos_angle)
      .attrs.text("units", "1")
      .text("long_name", "cosine of the scattering angle");
  if (!s.shape.spherical()) {
    std::vector<double> q;
    for (double r : t.radius_um) q.push_back(atmos::drop_axis_ratio(s.shape, r));
    ds.add("axis_ratio", {radius}, std::move(q))
        .attrs.text("units", "1")
        .text("long_name", "drop axis ratio (polar over equatorial) of each radius");
    coordinates += " axis_ratio";
  }
  std::vector<double> rgb(n * 3);
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) {
      const auto v = t.rgb(int(r), int(c));
      for (std::size_t k = 0; k < 3; ++k) rgb[(r * cols + c) * 3 + k] = v[k];
    }
  const std::string quantity = "per unit incident irradiance and unit projected-area optical depth of the drops";
  ds.add("rgb", {angle, radius, channel}, std::move(rgb))
      .attrs.text("units", "sr-1")
      .text("long_name", "linear RGB radiance scattered once " + quantity +
                             ", relative to the sun (sunlight is (1, 1, 1)), desaturated into the gamut at constant "
                             "luminance")
      .text("coordinates", coordinates);
  ds.add("xyz", {angle, radius, component}, t.xyz)
      .attrs.text("units", "sr-1")
      .text("long_name", "CIE 1931 XYZ of the radiance scattered once " + quantity +
                             ", relative to the sun's luminance (Y is the luminance), unmapped")
      .text("coordinates", coordinates);
  ds.add("display", {angle, radius, channel}, im.display)
      .attrs.text("units", "1")
      .text("long_name", "tone-mapped display value in [0, 1], linear (apply the sRGB curve to show it): Reinhard et "
                         "al. 2002's photographic operator on luminance, hue kept")
      .text("coordinates", coordinates);
  if (s.stokes) {
    ds.add("q_xyz", {angle, radius, component}, t.q_xyz)
        .attrs.text("units", "sr-1")
        .text("long_name", "Stokes Q weighted as xyz, in the scattering-plane basis (> 0: polarised tangentially to "
                           "the bow; U = V = 0 in this basis)")
        .text("coordinates", coordinates);
    std::vector<double> dolp(n);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) dolp[r * cols + c] = t.dolp(int(r), int(c));
    ds.add("dolp", {angle, radius}, std::move(dolp))
        .attrs.text("units", "1")
        .text("long_name", "luminance-weighted degree of linear polarisation Q_Y / I_Y (signed as Q; 0 where I_Y = 0)")
        .text("coordinates", coordinates);
  }
  std::vector<double> m;
  for (const auto& row : t.xyz_to_rgb)
    for (double v : row) m.push_back(v);
  ds.add("xyz_to_rgb", {channel, component}, std::move(m))
      .attrs.text("units", "1")
      .text("long_name", "matrix from xyz to linear RGB (Bradford adaptation from the sun's white to D65, then the "
                         "primaries), before gamut mapping");
  ds.add("sun_white_xyz", {component}, std::vector<double>{t.sun_white.X, t.sun_white.Y, t.sun_white.Z})
      .attrs.text("units", "1")
      .text("long_name", "the sun's XYZ over the sampled wavelengths, Y = 1");

  auto& a = ds.attrs;
  a.text("Conventions", "CF-1.8")
      .text("title", fmt::format("hydrolux {} table ({} theory)", atmos::table_kind_name(s.table), scatter::theory_name(s.theory)))
      .text("source", fmt::format("hydrolux {}", kVersion))
      .text("history", std::string(history))
      .text("references", "Lee, R. L., Jr. (1998): Mie theory, Airy theory, and the natural rainbow. Applied Optics "
                          "37(9), 1506-1519 (the Lee diagram)")
      .text("comment", "T = <dsigma_sca/dOmega> / <pi a^2>: radiance scattered once per unit incident irradiance per "
                       "unit projected-area optical depth of the drops (L = E_sun tau_geo T; tau_geo = path x sum pi "
                       "a^2 n(a), = tau_ext / 2 for drops much larger than the wavelength), averaged over the size "
                       "distribution, the sun's disk and the spectrum; each sample averaged over its row's cell")
      .text("table", atmos::table_kind_name(s.table))
      .text("theory", scatter::theory_name(s.theory))
      .text("angle_axis", atmos::angle_axis_name(s.axis))
      .text("radius_scale", atmos::radius_scale_name(s.radius_scale))
      .text("color_space", color::rgb_space_name(s.rgb_space))
      .text("sun", s.sun.name())
      .number("sun_disk_diameter_deg", s.sun_disk_deg)
      .integer("limb_darkening", s.limb_darkening ? 1 : 0)
      .text("size_distribution", s.size_spread > 0 ? "gamma" : "monodisperse")
      .number("size_spread", s.size_spread)
      .text("drop_medium", s.drop_medium)
      .text("surrounding_medium", s.surrounding_medium);
  if (s.temperature_c) a.number("temperature_c", *s.temperature_c);
  a.text("drop_shape", atmos::drop_shape_name(s.shape));
  if (!t.notes.empty()) a.text("resolution_notes", notes_text(t));
  if (t.error.luminance_rms) a.number("error_luminance_rms", *t.error.luminance_rms);
  if (t.error.q_rms) a.number("error_q_rms", *t.error.q_rms);
  if (!s.shape.spherical())
    a.number("sun_elevation_deg", s.sun_elevation_deg)
        .number("position_deg", s.position_deg)
        .number("canting_deg", s.canting_deg);
  a.number("sampling", s.sampling).integer("sampling_automatic", s.sampling_most > 0 ? 1 : 0);
  if (t.first_sampling && t.first_error)
    a.number("sampling_first_pass", *t.first_sampling).number("error_luminance_rms_first_pass", *t.first_error);
  a.integer("seed", std::int64_t(s.seed))
      .number("display_exposure", im.exposure)
      .number("display_white", im.white)
      .integer("evaluations", std::int64_t(t.work.evaluations));
  ds.check();
  return ds;
}

LeeFileBytes encode_lee_files(const atmos::LeeTable& t, const atmos::LeeImages& im, const LeeImageEncoder& encode) {
  static_assert(std::endian::native == std::endian::little, "the .f32 tables are little-endian");
  LeeFileBytes out;
  Image lin(t.columns(), t.rows(), t.spec.stokes ? 9 : 6);
  lin.channel_names = {"R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"};
  if (!t.spec.stokes) {
    lin.pixels.assign(im.linear.begin(), im.linear.end());
  } else {  // Q.X, Q.Y, Q.Z after the six
    const std::size_t n = std::size_t(t.columns()) * std::size_t(t.rows());
    for (std::size_t p = 0; p < n; ++p) {
      for (std::size_t c = 0; c < 6; ++c) lin.pixels[p * 9 + c] = im.linear[p * 6 + c];
      for (std::size_t c = 0; c < 3; ++c) lin.pixels[p * 9 + 6 + c] = float(t.q_xyz[p * 3 + c]);
    }
    lin.channel_names.insert(lin.channel_names.end(), {"Q.X", "Q.Y", "Q.Z"});
  }
  Image disp(t.columns(), t.rows(), 3);
  disp.pixels.assign(im.display.begin(), im.display.end());
  out.exr = encode(lin, io::ImageFormat::exr, {});
  out.png = encode(disp, io::ImageFormat::png, {});
  std::vector<float> rgb(std::size_t(t.columns()) * t.rows() * 3);
  for (std::size_t p = 0; p < std::size_t(t.columns()) * t.rows(); ++p)
    for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = im.linear[p * 6 + c];
  out.f32.resize(rgb.size() * sizeof(float));
  std::memcpy(out.f32.data(), rgb.data(), out.f32.size());
  return out;
}

LeeSidecarAxes parse_lee_sidecar(std::string_view json_text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json_text);
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("not valid JSON ({})", e.what()));
  }
  LeeSidecarAxes a;
  try {
    if (!j.is_object() || j.value("format", "") != "hydrolux-lee-table") throw Error("not a hydrolux Lee table");
    const std::string k = j.at("table").get<std::string>();
    if (k == "rainbow") a.kind = atmos::LeeTableKind::rainbow;
    else if (k == "corona") a.kind = atmos::LeeTableKind::corona;
    else if (k == "glory") a.kind = atmos::LeeTableKind::glory;
    else throw Error(fmt::format("unknown table kind '{}'", printable(k)));
    const std::string ax = j.at("axis").get<std::string>();
    if (ax != "angle" && ax != "cos") throw Error(fmt::format("unknown axis '{}'", printable(ax)));
    a.axis = ax == "cos" ? atmos::AngleAxis::cosine : atmos::AngleAxis::angle;
    const std::string scale = j.at("radius_scale").get<std::string>();
    if (scale != "log" && scale != "linear") throw Error(fmt::format("unknown radius_scale '{}'", printable(scale)));
    a.radius_scale = scale == "log" ? atmos::RadiusScale::log : atmos::RadiusScale::linear;
    a.radius_um = j.at("radius_um").get<std::vector<double>>();
    a.rows = j.at(a.axis == atmos::AngleAxis::angle ? "angle_deg" : "cos_angle").get<std::vector<double>>();
    if (j.contains("stokes")) {
      const auto m = j.at("color_space").at("xyz_to_rgb").get<std::vector<std::vector<double>>>();
      color::Mat3 mat{};
      if (m.size() != 3) throw Error("color_space.xyz_to_rgb is not a 3 x 3 matrix");
      for (std::size_t r = 0; r < 3; ++r) {
        if (m[r].size() != 3) throw Error("color_space.xyz_to_rgb is not a 3 x 3 matrix");
        for (std::size_t c = 0; c < 3; ++c) {
          if (!std::isfinite(m[r][c]) || std::abs(m[r][c]) > 100)
            throw Error(fmt::format("color_space.xyz_to_rgb holds {:g} (finite, |x| <= 100)", m[r][c]));
          mat[r][c] = m[r][c];
        }
      }
      a.stokes_xyz_to_rgb = mat;
    }
  } catch (const nlohmann::json::exception& e) {
    throw Error(fmt::format("the table's axes are missing or malformed ({})", e.what()));
  }
  return a;
}

scene::BowTable lee_bow_table(LeeSidecarAxes axes, const io::DecodedImage& decoded) {
  auto& radii = axes.radius_um;
  auto& rows = axes.rows;
  if (decoded.format != io::ImageFormat::exr)
    throw Error(fmt::format("the file is {} by its content, not OpenEXR (a table holds linear sr^-1 values; a "
                            "renamed display image does not)",
                            io::format_name(decoded.format)));
  const Image& im = decoded.image;
  if (im.channels < 3) throw Error("the EXR has fewer than 3 channels");
  if (im.width != int(radii.size()) || im.height != int(rows.size()))
    throw Error(fmt::format("the EXR is {}x{} but its sidecar describes {} radii x {} rows", im.width, im.height,
                            radii.size(), rows.size()));
  const std::size_t n = std::size_t(im.width) * im.height;
  std::vector<float> rgb(n * 3);
  for (std::size_t q = 0; q < n; ++q)
    for (int c = 0; c < 3; ++c) rgb[q * 3 + c] = im.pixels[q * std::size_t(im.channels) + c];
  std::vector<float> q_rgb;
  if (axes.stokes_xyz_to_rgb) {
    // The channels by name: Y's and Q's XYZ.
    const auto& names = decoded.channel_names;
    const auto channel = [&](const char* name) {
      const auto it = std::find(names.begin(), names.end(), name);
      if (it == names.end())
        throw Error(fmt::format("the sidecar says the table has the Stokes Q, but the EXR has no channel {}", name));
      return std::size_t(it - names.begin());
    };
    const std::size_t qx = channel("Q.X"), qy = channel("Q.Y"), qz = channel("Q.Z"), iy = channel("XYZ.Y");
    const auto& m = *axes.stokes_xyz_to_rgb;
    q_rgb.resize(n * 3);
    for (std::size_t p = 0; p < n; ++p) {
      const float* v = &im.pixels[p * std::size_t(im.channels)];
      // |Q| <= I in every band: Q_Y against I_Y (a small slack for the half floats' rounding).
      if (!(std::abs(v[qy]) <= std::abs(v[iy]) * 1.001f + 1e-30f))
        throw Error(fmt::format("the Stokes Q_Y {:g} exceeds the intensity Y {:g} at row {}, column {} (|Q| <= I)",
                                v[qy], v[iy], p / std::size_t(im.width), p % std::size_t(im.width)));
      for (std::size_t c = 0; c < 3; ++c)
        q_rgb[p * 3 + c] = float(m[c][0] * v[qx] + m[c][1] * v[qy] + m[c][2] * v[qz]);
    }
  }
  return scene::bow_table(axes.kind, axes.axis, std::move(radii), rows, std::move(rgb), axes.radius_scale,
                          std::move(q_rgb));
}

}  // namespace hydrolux::io
