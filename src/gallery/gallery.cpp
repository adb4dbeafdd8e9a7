#include "hydrolux/gallery/gallery.hpp"

#include "entries.hpp"

#include <fmt/format.h>

#include <functional>
#include <tuple>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"
#include "hydrolux/io/svg_plot.hpp"
#include "hydrolux/optics/bsdf.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/optics/snell.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::gallery {

detail::Entry detail::image_entry(std::string file, std::string title, std::string caption,
                                  std::function<Image()> make) {
  Entry e;
  e.figure = {std::move(file), std::move(title), std::move(caption)};
  e.render = [make = std::move(make)] { return io::encode_image(make(), io::ImageFormat::png); };
  return e;
}

detail::Entry detail::plot_entry(std::string file, std::string title, std::string caption,
                                 std::function<io::Plot()> make) {
  Entry e;
  e.figure = {std::move(file), std::move(title), std::move(caption)};
  e.render = [make = std::move(make)] { return io::render_svg(make()); };
  return e;
}

namespace {

using io::Plot;
using io::PlotMarker;
using io::PlotSeries;

constexpr const char* kBlue = "#1f77b4";
constexpr const char* kOrange = "#ff7f0e";
constexpr const char* kBlack = "#222222";
constexpr const char* kGreen = "#2ca02c";
constexpr const char* kRed = "#d62728";
constexpr const char* kPurple = "#9467bd";
constexpr const char* kBrown = "#8c564b";

using detail::Entry;
using detail::plot_entry;

struct Axis {
  double min, max, tick;
};

Plot axes(std::string title, std::string x_label, std::string y_label, Axis x, Axis y,
          io::LegendCorner legend = io::LegendCorner::TopLeft) {
  Plot p;
  p.title = std::move(title);
  p.x_label = std::move(x_label);
  p.y_label = std::move(y_label);
  p.x_min = x.min, p.x_max = x.max, p.x_tick = x.tick;
  p.y_min = y.min, p.y_max = y.max, p.y_tick = y.tick;
  p.legend = legend;
  return p;
}

// A series y = fn(x) for x = from, from + step, ... <= to.
template <typename Fn>
PlotSeries curve(std::string label, const char* colour, double from, double to, double step, Fn fn,
                 bool dashed = false) {
  PlotSeries s{std::move(label), {}, {}, colour, dashed};
  for (int i = 0;; ++i) {
    const double x = from + step * i;
    if (x > to + 1e-9 * step) break;
    s.x.push_back(x);
    s.y.push_back(fn(x));
  }
  return s;
}

std::vector<double> angles_deg() {
  std::vector<double> a;
  for (int i = 0; i <= 360; ++i) a.push_back(0.25 * i);
  return a;
}

// R_s, R_p, R (and T for dielectrics) against the angle of incidence, n1 -> n2 + i k2.
Plot fresnel_plot(const std::string& title, double n1, std::complex<double> n2) {
  Plot p = axes(title, "angle of incidence (degrees)", "reflectance", {0, 90, 10}, {0, 1, 0.1});
  PlotSeries rs{"R_s (perpendicular)", {}, {}, kBlue}, rp{"R_p (parallel)", {}, {}, kOrange},
      r{"R (unpolarised)", {}, {}, kBlack}, t{"T = 1 - R (transmitted)", {}, {}, kGreen, true};
  const bool conductor = n2.imag() > 0;
  for (double a : angles_deg()) {
    const double c = std::cos(deg_to_rad(a));
    double vs, vp, v, vt = 0;
    if (conductor) {
      const auto f = optics::fresnel_conductor(c, n1, n2);
      vs = f.R_s, vp = f.R_p, v = f.R;
    } else {
      const auto f = optics::fresnel_dielectric(c, n1, n2.real());
      vs = f.R_s, vp = f.R_p, v = f.R, vt = f.T;
    }
    for (auto* s : {&rs, &rp, &r, &t}) s->x.push_back(a);
    rs.y.push_back(vs), rp.y.push_back(vp), r.y.push_back(v), t.y.push_back(vt);
  }
  p.series = {rs, rp, r};
  if (!conductor) {
    p.series.push_back(t);
    p.markers.push_back({rad_to_deg(optics::brewster_angle(n1, n2.real())),
                         fmt::format("Brewster {:.2f} deg", rad_to_deg(optics::brewster_angle(n1, n2.real()))),
                         kOrange});
    if (auto crit = optics::critical_angle(n1, n2.real()))
      p.markers.push_back({rad_to_deg(*crit), fmt::format("critical {:.2f} deg", rad_to_deg(*crit)), kRed});
  }
  return p;
}

// A water drop in air, its radius in um, at a vacuum wavelength in nm.
scatter::SphereProblem water_drop(double radius_um, double lambda_nm) {
  return scatter::sphere_problem(radius_um, lambda_nm, *optics::find_medium("water"), *optics::find_medium("air"));
}

std::string n_text(std::complex<double> n) {
  return n.imag() > 0 ? fmt::format("{:.4f} + {:.4f}i", n.real(), n.imag()) : fmt::format("{:.5f}", n.real());
}

// The indices of the Fresnel figures: water at the sodium D line and 20 C (IAPWS R9-97), N-BK7 at
// the helium d line, gold at 550 nm.
constexpr double kWaterNm = 589.3;
double water_n() { return optics::find_medium("water")->n(kWaterNm, 20.0); }
double bk7_n() { return optics::find_medium("bk7")->n(587.6); }
std::complex<double> gold_n() { return optics::find_medium("gold")->index(550.0); }

Entry fresnel_air_water_figure() {
  return plot_entry(
      "fresnel_air_water.svg", "Fresnel: air to water",
      fmt::format("Reflectance of a still water surface seen from air at {} nm, 20 C (n = {}, "
                  "IAPWS R9-97). R_p vanishes at Brewster's angle; every curve rises to 1 "
                  "at grazing incidence.",
                  kWaterNm, n_text(water_n())),
      [] {
        const double n_w = water_n();
        return fresnel_plot(fmt::format("Air to water, {} nm (n = {:.4f})", kWaterNm, n_w), 1.0, n_w);
      });
}

Entry fresnel_water_air_figure() {
  return plot_entry(
      "fresnel_water_air.svg", "Fresnel: water to air (inside a drop)",
      fmt::format("The same interface seen from inside the water, as by light inside a rain "
                  "drop: past the critical angle asin(1/n) = {:.2f} degrees all light is "
                  "reflected (total internal reflection).",
                  rad_to_deg(*optics::critical_angle(water_n(), 1.0))),
      [] {
        const double n_w = water_n();
        auto p = fresnel_plot(fmt::format("Water to air, {} nm (n = {:.4f})", kWaterNm, n_w), n_w, 1.0);
        p.legend = io::LegendCorner::BottomRight;
        return p;
      });
}

Entry fresnel_air_glass_figure() {
  return plot_entry(
      "fresnel_air_glass.svg", "Fresnel: air to glass (N-BK7)",
      fmt::format("Crown glass N-BK7 at 587.6 nm (n = {}, SCHOTT Sellmeier, made absolute). "
                  "At normal incidence about 4% is reflected.",
                  n_text(bk7_n())),
      [] {
        const double n_g = bk7_n();
        return fresnel_plot(fmt::format("Air to N-BK7 glass, 587.6 nm (n = {:.4f})", n_g), 1.0, n_g);
      });
}

Entry fresnel_air_gold_figure() {
  return plot_entry(
      "fresnel_air_gold.svg", "Fresnel: air to gold",
      fmt::format("Gold at 550 nm (n = {}, Johnson & Christy 1972), exact complex Fresnel "
                  "equations. R_p dips at the principal angle but never reaches zero; "
                  "what is not reflected is absorbed.",
                  n_text(gold_n())),
      [] {
        auto p = fresnel_plot("Air to gold, 550 nm", 1.0, gold_n());
        p.legend = io::LegendCorner::BottomLeft;
        return p;
      });
}

Entry rough_water_albedo_figure() {
  return plot_entry(
      "rough_water_albedo.svg", "Rough water surface (microfacet BSDF)",
      fmt::format("Light arriving from air on a rough water surface (n = {:.4f}): the "
                  "fractions reflected (rising at grazing) and transmitted, from the Walter "
                  "et al. (2007) BSDF with a GGX distribution, by importance sampling (20000 "
                  "samples per point). Smooth Fresnel in black. At roughness 0.6 the sum "
                  "falls below 1, to about 0.8 near grazing incidence: single-scattering microfacet "
                  "models lose the light that masking blocks.",
                  water_n()),
      [] {
        const double n_w = water_n();
        Plot p = axes("Rough air-water interface: reflected and transmitted power",
                      "angle of incidence (degrees)", "fraction of incident power",
                      {0, 90, 10}, {0, 1, 0.1}, io::LegendCorner::CenterLeft);
        const auto smooth = [n_w](double a) {
          return optics::fresnel_dielectric(std::cos(deg_to_rad(a)), 1.0, n_w).R;
        };
        p.series = {curve("smooth: R (Fresnel)", kBlack, 0, 89, 0.5, smooth),
                    curve("smooth: T = 1 - R", kBlack, 0, 89, 0.5,
                          [&](double a) { return 1 - smooth(a); }, true)};
        const std::pair<double, const char*> roughness[] = {{0.1, kBlue}, {0.3, kGreen}, {0.6, kRed}};
        for (const auto& [alpha, colour] : roughness) {
          const optics::RoughDielectric bsdf(
              optics::MicrofacetDistribution::trowbridge_reitz(alpha, alpha), n_w);
          PlotSeries r{fmt::format("GGX alpha {:g}: reflected", alpha), {}, {}, colour};
          PlotSeries t{fmt::format("GGX alpha {:g}: transmitted", alpha), {}, {}, colour, true};
          for (int i = 0; i <= 44; ++i) {
            const double a = 2.0 * i;
            const auto alb = optics::directional_albedo(
                bsdf, spherical_direction(deg_to_rad(a), 0.0), 20000, 1000 + i);
            r.x.push_back(a), r.y.push_back(alb.reflected);
            t.x.push_back(a), t.y.push_back(alb.transmitted);
          }
          p.series.push_back(r);
          p.series.push_back(t);
        }
        return p;
      });
}

Entry mie_phase_functions_figure() {
  return plot_entry(
      "mie_phase_functions.svg", "Mie phase functions of water drops",
      "Lorenz-Mie phase function p(theta) (normalised: its mean over the sphere is 1) of "
      "single water drops in air at 550 nm, unpolarised light. Larger drops throw more light "
      "forward (diffraction); the primary rainbow near 138 degrees and the glory towards 180 "
      "degrees grow out of the oscillations as the drop grows.",
      [] {
        Plot p = axes("Mie phase function, water drops at 550 nm", "scattering angle (degrees)",
                      "phase function p(theta)", {0, 180, 20}, {1e-3, 1e6, 1},
                      io::LegendCorner::TopRight);
        p.y_log = true;
        std::vector<double> theta, mu;
        for (int i = 0; i <= 1800; ++i) {
          theta.push_back(0.1 * i);
          mu.push_back(std::cos(deg_to_rad(0.1 * i)));
        }
        const std::pair<double, const char*> drops[] = {{1, kGreen}, {10, kBlue}, {100, kRed}};
        for (const auto& [radius_um, colour] : drops) {
          const auto sp = water_drop(radius_um, 550.0);
          PlotSeries s{fmt::format("r = {:g} um (x = {:.0f})", radius_um, sp.x), theta,
                       scatter::mie_phase_function(scatter::mie_coefficients(sp.m, sp.x), mu), colour};
          p.series.push_back(s);
        }
        return p;
      });
}

Entry rainbow_theories_figure() {
  return plot_entry(
      "rainbow_theories.svg", "The primary rainbow of one drop, four theories",
      "A 250 um water drop in air at 650 nm (x = 2415), perpendicular polarisation, near the "
      "primary rainbow. Lorenz-Mie is exact; its Debye p = 2 term keeps only the light "
      "reflected once inside the drop (the rainbow rays) and follows Mie's main bow and "
      "supernumeraries, while the full Mie curve adds the ripple of the other orders. Airy "
      "theory reproduces the main bow and supernumeraries. Geometric optics with interference "
      "(rays of orders 0-2, so it has the ripple too) diverges at the caustic, the "
      "geometric rainbow angle (dotted).",
      [] {
        Plot p = axes("Primary rainbow, r = 250 um, 650 nm, perpendicular polarisation",
                      "scattering angle (degrees)", "intensity i1 / x^2", {136, 142, 1},
                      {0, 1.2, 0.1}, io::LegendCorner::TopRight);
        const auto sp = water_drop(250.0, 650.0);
        std::vector<double> deg, rad;
        for (int i = 0; i <= 1200; ++i) {
          deg.push_back(136.0 + 0.005 * i);
          rad.push_back(deg_to_rad(deg.back()));
        }
        const std::tuple<const char*, const char*, const char*, bool> theories[] = {
            {"mie", "Lorenz-Mie (exact)", kBlack, false},
            {"debye:2", "Debye p = 2", kBlue, false},
            {"airy", "Airy theory", kOrange, true},
            {"geometric:2", "geometric optics, orders 0-2", kGreen, true}};
        for (const auto& [name, label, colour, dashed] : theories) {
          std::vector<scatter::Complex> s1(rad.size()), s2(rad.size());
          scatter::amplitudes(scatter::parse_theory(name), sp.m, sp.x, rad, s1, s2);
          PlotSeries s{label, deg, {}, colour, dashed};
          for (const auto& v : s1) s.y.push_back(std::norm(v) / (sp.x * sp.x));
          p.series.push_back(s);
        }
        const double geometric = rad_to_deg(scatter::rainbow_angle(sp.m.real(), 2));
        p.markers.push_back({geometric, fmt::format("geometric {:.2f} deg", geometric), kGreen});
        return p;
      });
}

Entry drop_radiance_profile_figure() {
  return plot_entry(
      "drop_radiance_profile.svg", "A rain drop's radiance, path by path (Garg & Nayar Fig. 4)",
      fmt::format("Radiance leaving a water drop (mu = 1.333) towards the camera along each path, for "
                  "a uniform environment (Le = 1) and the drop on the optical axis, against the "
                  "distance rho from the centre of the drop's image (1 = rim). Refraction carries "
                  "96% of the light at the centre, 92% at rho 0.8 and 84% at 0.9; near the rim reflection takes over "
                  "(half at rho 0.98). The "
                  "refracted rays see a {:.1f} degree field of view (the paper: about 165). "
                  "Checked against an exact ray trace of the sphere.",
                  drop::field_of_view_deg(1.333)),
      [] {
        Plot p = axes("Drop radiance by path, Le = 1, mu = 1.333", "rho (0 = centre, 1 = rim)",
                      "radiance", {0, 1, 0.1}, {1e-4, 2, 1}, io::LegendCorner::BottomLeft);
        p.y_log = true;
        const auto f = drop::radiance_profile(1.333, 501);
        p.series = {{"refraction (1-k)^2", f.rho, f.refraction, kBlue},
                    {"specular reflection k", f.rho, f.reflection, kRed},
                    {"1 internal reflection k(1-k)^2", f.rho, f.internal[0], kGreen},
                    {"2 internal reflections k^2(1-k)^2", f.rho, f.internal[1], kOrange}};
        return p;
      });
}

Entry metals_normal_incidence_figure() {
  return plot_entry(
      "metals_normal_incidence.svg", "Metals at normal incidence",
      "Normal-incidence reflectance R = ((n-1)^2 + k^2) / ((n+1)^2 + k^2) of the built-in "
      "metals across the visible: gold and copper reflect red better than blue, which is "
      "their colour; aluminium dips near 800 nm (interband absorption).",
      [] {
        Plot p = axes("Normal-incidence reflectance of metals", "vacuum wavelength (nm)",
                      "reflectance", {300, 1000, 100}, {0, 1, 0.1},
                      io::LegendCorner::BottomRight);
        const std::pair<const char*, const char*> metals[] = {
            {"silver", "#7f7f7f"}, {"aluminium", kBlue}, {"gold", "#c9a000"}, {"copper", kBrown}};
        for (const auto& [name, colour] : metals) {
          const auto m = optics::find_medium(name);
          p.series.push_back(curve(name, colour, 300, 1000, 2.5, [&](double l) {
            return optics::fresnel_conductor(1.0, 1.0, m->index(l)).R;
          }));
        }
        return p;
      });
}

Entry dispersion_figure() {
  return plot_entry(
      "dispersion.svg", "Dispersion n(lambda)",
      "Refractive index against wavelength of the built-in transparent media, each within "
      "its source's valid range (PMMA's fit starts at 436.8 nm). Water's dispersion is what "
      "separates the colours of a rainbow.",
      [] {
        // The y range leaves room for the legend between water and fused silica.
        Plot p = axes("Refractive index of transparent media", "vacuum wavelength (nm)",
                      "refractive index n", {400, 1000, 100}, {1.26, 1.54, 0.02},
                      io::LegendCorner::CenterRight);
        const std::tuple<const char*, const char*, const char*> media[] = {
            {"bk7", "N-BK7 glass", kRed},
            {"pmma", "PMMA (acrylic)", kPurple},
            {"fused-silica", "fused silica", kGreen},
            {"water", "water, 20 C", kBlue},
            {"ice", "ice Ih, -7 C", "#17becf"}};
        for (const auto& [name, label, colour] : media) {
          const auto m = optics::find_medium(name);
          const double from = std::ceil(std::max(400.0, m->info().lambda_min_nm) / 2) * 2;
          const double to = std::min(1000.0, m->info().lambda_max_nm);
          p.series.push_back(curve(label, colour, from, to, 2, [&](double l) { return m->n(l); }));
        }
        return p;
      });
}

Entry water_temperature_figure() {
  return plot_entry(
      "water_temperature.svg", "Water: index against temperature",
      "IAPWS R9-97 refractive index of liquid water at 0.1 MPa from 0 to 100 C at three "
      "wavelengths; the density comes from Kell (1975). Warmer water is less dense and "
      "refracts less.",
      [] {
        const auto water = optics::find_medium("water");
        Plot p = axes("Liquid water: n against temperature (IAPWS R9-97)", "temperature (C)",
                      "refractive index n", {0, 100, 10}, {1.315, 1.345, 0.005},
                      io::LegendCorner::TopRight);
        const std::pair<double, const char*> lines[] = {{450, kBlue}, {550, kGreen}, {650, kRed}};
        for (const auto& [l, colour] : lines)
          p.series.push_back(curve(fmt::format("{:g} nm", l), colour, 0, 100, 1,
                                   [&](double t) { return water->n(l, t); }));
        return p;
      });
}

std::vector<Entry> entries() {
  std::vector<Entry> e = {fresnel_air_water_figure(), fresnel_water_air_figure(), fresnel_air_glass_figure(),
                          fresnel_air_gold_figure(), rough_water_albedo_figure(), mie_phase_functions_figure(),
                          rainbow_theories_figure(), drop_radiance_profile_figure(), metals_normal_incidence_figure(),
                          dispersion_figure(), water_temperature_figure()};
  for (const auto part : {detail::drop_entries, detail::lee_entries, detail::shape_entries, detail::sky_entries,
                          detail::rain_entries, detail::lens_drops_entries, detail::fog_entries})
    for (auto& d : part()) e.push_back(std::move(d));
  return e;
}

std::string index_html(const std::vector<Figure>& figures) {
  std::string h = fmt::format(R"(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>hydrolux gallery</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1540px; color: #222; }}
h1 {{ margin-bottom: 0.2em; }}
.grid {{ display: grid; grid-template-columns: repeat(auto-fill, minmax(720px, 1fr)); gap: 1.5em; }}
figure {{ margin: 0; border: 1px solid #ddd; padding: 0.5em; background: #fff; }}
figure img {{ width: 100%; height: auto; }}
figcaption {{ font-size: 0.92em; line-height: 1.4; }}
</style>
</head>
<body>
<h1>hydrolux gallery</h1>
<p>Made by <code>hydrolux gallery</code> (hydrolux {}) from built-in data, with no input files.</p>
<div class="grid">
)",
                              kVersion);
  for (const auto& f : figures)
    h += fmt::format("<figure><img src=\"{0}\" alt=\"{1}\"><figcaption><b>{1}.</b> {2}</figcaption></figure>\n",
                     f.file, f.title, f.caption);
  h += "</div>\n</body>\n</html>\n";
  return h;
}

}  // namespace

std::vector<Figure> render_gallery(const FigureSink& sink, const ProgressFn& progress) {
  const auto all = entries();
  std::vector<Figure> figures;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (progress) progress(double(i) / double(all.size() + 1), all[i].figure.file);
    sink(all[i].figure.file, all[i].render());
    figures.push_back(all[i].figure);
  }
  if (progress) progress(double(all.size()) / double(all.size() + 1), "index.html");
  sink("index.html", index_html(figures));
  if (progress) progress(1.0, "done");
  return figures;
}

std::vector<Figure> write_gallery(const std::filesystem::path& dir, const ProgressFn& progress) {
  io::OutputDirectory out(dir);
  const auto figures =
      render_gallery([&](const std::string& name, std::string_view bytes) { out.write(name, bytes); }, progress);
  out.commit();
  return figures;
}

}  // namespace hydrolux::gallery
