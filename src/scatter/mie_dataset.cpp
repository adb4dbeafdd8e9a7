#include "hydrolux/scatter/mie_dataset.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/version.hpp"

namespace hydrolux::scatter {

namespace {
std::vector<double> copy(std::span<const double> v) { return {v.begin(), v.end()}; }

// S1, S2 (and the Mueller elements, and the phase function) over (size_parameter, scattering_angle).
void add_angular(Dataset& ds, const MieDatasetInput& in, const std::string& size, const std::string& angle,
                 const std::string& coordinates) {
  const std::size_t n = in.x.size(), a = in.angles_deg.size();
  const auto field = [&](const char* name, std::vector<double> v, const std::string& units,
                         const std::string& long_name) {
    auto& var = ds.add(name, {size, angle}, std::move(v));
    var.attrs.text("units", units).text("long_name", long_name);
    if (!coordinates.empty()) var.attrs.text("coordinates", coordinates);
  };
  const auto part = [&](std::span<const Complex> s, bool imag) {
    std::vector<double> v(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) v[i] = imag ? s[i].imag() : s[i].real();
    return v;
  };
  const std::string which = in.debye_p ? fmt::format(" of Debye order p = {} alone", *in.debye_p) : std::string();
  field("s1_real", part(in.s1, false), "1", "real part of the scattering amplitude S1 (perpendicular)" + which);
  field("s1_imag", part(in.s1, true), "1", "imaginary part of the scattering amplitude S1 (perpendicular)" + which);
  field("s2_real", part(in.s2, false), "1", "real part of the scattering amplitude S2 (parallel)" + which);
  field("s2_imag", part(in.s2, true), "1", "imaginary part of the scattering amplitude S2 (parallel)" + which);
  if (!in.s11.empty()) {
    field("s11", copy(in.s11), "1", "Mueller element S11 = (|S2|^2 + |S1|^2) / 2" + which);
    field("s12", copy(in.s12), "1", "Mueller element S12 = (|S2|^2 - |S1|^2) / 2" + which);
    field("s33", copy(in.s33), "1", "Mueller element S33 = Re(S2 S1*)" + which);
    field("s34", copy(in.s34), "1", "Mueller element S34 = Im(S2 S1*)" + which);
  }
  if (!in.debye_p) {
    std::vector<double> p(n * a);
    for (std::size_t i = 0; i < n; ++i) {
      const double norm = std::numbers::pi * in.x[i] * in.x[i] * in.qsca[i];
      for (std::size_t j = 0; j < a; ++j) {
        const std::size_t k = i * a + j;
        p[k] = norm > 0 ? 0.5 * (std::norm(in.s1[k]) + std::norm(in.s2[k])) / norm : 0.0;
      }
    }
    field("phase_function", std::move(p), "sr-1",
          "phase function (|S1|^2 + |S2|^2) / 2 / (pi x^2 Q_sca), normalised to 1 over the sphere (the library's "
          "mie_phase_function / 4 pi)");
  }
}

}  // namespace

MieDatasetInput one_sphere(Complex m, const double& x, const MieEfficiencies& q, const int& n_terms,
                           std::span<const double> angles_deg, std::span<const Complex> s1,
                           std::span<const Complex> s2, const MuellerElements* mueller) {
  MieDatasetInput in;
  in.m = m;
  in.x = {&x, 1};
  in.qext = {&q.qext, 1}, in.qsca = {&q.qsca, 1}, in.qabs = {&q.qabs, 1}, in.qback = {&q.qback, 1};
  in.g = {&q.g, 1};
  in.n_terms = {&n_terms, 1};
  in.angles_deg = angles_deg, in.s1 = s1, in.s2 = s2;
  if (mueller) in.s11 = mueller->s11, in.s12 = mueller->s12, in.s33 = mueller->s33, in.s34 = mueller->s34;
  return in;
}

Dataset mie_dataset(const MieDatasetInput& in, std::string_view history) {
  const std::size_t n = in.x.size(), a = in.angles_deg.size();
  for (const auto* v : {&in.qext, &in.qsca, &in.qabs, &in.qback, &in.g})
    if (v->size() != n) throw Error("mie_dataset: an efficiency array's length differs from x's");
  if (in.n_terms.size() != n) throw Error("mie_dataset: n_terms' length differs from x's");
  if (in.s1.size() != n * a || in.s2.size() != n * a) throw Error("mie_dataset: S1, S2 are not x by angles");
  if (!in.s11.empty() && (in.s11.size() != n * a || in.s12.size() != n * a || in.s33.size() != n * a || in.s34.size() != n * a))
    throw Error("mie_dataset: the Mueller elements are not x by angles");
  const bool physical = in.wavelength_nm.has_value();
  if (physical && in.radius_um.size() != n) throw Error("mie_dataset: radius_um's length differs from x's");
  // Both label the dataset's axes: CF coordinates, which must be strictly monotonic.
  for (const auto& [name, values] : {std::pair{"x", in.x}, std::pair{"angles_deg", in.angles_deg}}) {
    try {
      parse::require_strictly_monotonic(values);
    } catch (const Error& e) {
      throw Error(fmt::format("{}: {} (a labelled dataset's coordinate; CF)", name, e.what()));
    }
  }

  Dataset ds;
  const std::string size = ds.dim("size_parameter", n);
  ds.add(size, {size}, copy(in.x))
      .attrs.text("units", "1")
      .text("long_name", "size parameter x = 2 pi r n_surrounding / lambda");
  const std::string angle = a ? ds.dim("scattering_angle", a) : std::string();
  if (a)
    ds.add(angle, {angle}, copy(in.angles_deg))
        .attrs.text("units", "degree")
        .text("long_name", "scattering angle (0 forward)");
  std::string coordinates;
  if (physical) {
    ds.add("radius", {size}, copy(in.radius_um)).attrs.text("units", "um").text("long_name", "sphere radius");
    coordinates = "radius";
  }
  const auto efficiency = [&](const char* name, std::span<const double> v, const std::string& long_name) {
    auto& var = ds.add(name, {size}, copy(v));
    var.attrs.text("units", "1").text("long_name", long_name);
    if (!coordinates.empty()) var.attrs.text("coordinates", coordinates);
  };
  efficiency("qext", in.qext, "extinction efficiency Q_ext = C_ext / (pi r^2)");
  efficiency("qsca", in.qsca, "scattering efficiency Q_sca = C_sca / (pi r^2)");
  efficiency("qabs", in.qabs, "absorption efficiency Q_abs = Q_ext - Q_sca");
  efficiency("qback", in.qback, "backscattering efficiency Q_back = 4 |S1(180 deg)|^2 / x^2 (Bohren & Huffman)");
  efficiency("g", in.g, "asymmetry parameter <cos theta>");
  ds.add("n_terms", {size}, std::vector<std::int32_t>(in.n_terms.begin(), in.n_terms.end()))
      .attrs.text("units", "1")
      .text("long_name", "partial waves summed");
  if (a) add_angular(ds, in, size, angle, coordinates);
  auto& at = ds.attrs;
  at.text("Conventions", "CF-1.8")
      .text("title", "hydrolux Lorenz-Mie scattering by homogeneous spheres")
      .text("source", fmt::format("hydrolux {}", kVersion))
      .text("history", history)
      .text("references", "Bohren, C. F. and Huffman, D. R. (1983): Absorption and Scattering of Light by Small "
                          "Particles, Wiley (conventions: S1, S2 and the Mueller elements, eq. 4.77)")
      .number("m_real", in.m.real())
      .number("m_imag", in.m.imag())
      .text("comment", "m_real, m_imag: the relative complex refractive index m = m_real + i m_imag (m_imag >= 0 "
                       "absorbs)");
  if (in.debye_p) at.integer("debye_p", *in.debye_p);
  if (physical) {
    at.number("wavelength_nm", *in.wavelength_nm).text("medium", in.medium).text("surrounding", in.surrounding);
    if (in.temperature_c) at.number("temperature_c", *in.temperature_c);
  }
  ds.check();
  return ds;
}

}  // namespace hydrolux::scatter
