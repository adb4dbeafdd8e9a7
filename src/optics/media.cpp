#include "hydrolux/optics/media.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>

#include "hydrolux/core/embedded_data.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/table.hpp"

namespace hydrolux::optics {

std::complex<double> Medium::index(double lambda_nm, std::optional<double> temperature_c) const {
  const auto& i = info();
  const std::string& context = i.name;
  require_in_range("wavelength_nm", lambda_nm, i.lambda_min_nm, i.lambda_max_nm, context);
  const double t = temperature_c.value_or(i.default_temperature_c);
  require_in_range("temperature_c", t, i.temperature_min_c, i.temperature_max_c, context);
  return index_in_range(lambda_nm, t);
}

namespace {

// ---------------------------------------------------------------------------------------------
// Tabulated n and k (data/media/*.csv, embedded at build time).

struct NkTable {
  Table table;
  std::span<const double> lambda, n, k;
  explicit NkTable(std::string_view path)
      : table(parse_table(embedded_file(path), path)),
        lambda(table.column("wavelength_nm")),
        n(table.column("n")),
        k(table.column("k")) {
    for (std::size_t i = 1; i < lambda.size(); ++i)
      if (!(lambda[i] > lambda[i - 1]))
        throw IoError(fmt::format("{}: wavelengths are not strictly increasing", path));
  }
  double interpolate_n(double lambda_nm) const { return interpolate_linear(lambda, n, lambda_nm); }
  // k spans orders of magnitude in transparent media: interpolate log k where both ends are > 0.
  double interpolate_k(double lambda_nm) const {
    const auto it = std::upper_bound(lambda.begin(), lambda.end(), lambda_nm);
    if (it == lambda.begin()) return k.front();
    if (it == lambda.end()) return k.back();
    const auto i = static_cast<std::size_t>(it - lambda.begin());
    const double t = (lambda_nm - lambda[i - 1]) / (lambda[i] - lambda[i - 1]);
    if (k[i - 1] > 0 && k[i] > 0) return k[i - 1] * std::pow(k[i] / k[i - 1], t);
    return k[i - 1] + t * (k[i] - k[i - 1]);
  }
};

class TabulatedMedium final : public Medium {
 public:
  TabulatedMedium(MediumInfo info, std::shared_ptr<const NkTable> table)
      : Medium(std::move(info)), table_(std::move(table)) {}

 protected:
  std::complex<double> index_in_range(double lambda_nm, double) const override {
    return {table_->interpolate_n(lambda_nm), table_->interpolate_k(lambda_nm)};
  }

 private:
  std::shared_ptr<const NkTable> table_;
};

// Media with a closed-form n(lambda) and k = 0. The formula takes the wavelength in micrometres.
class FormulaMedium final : public Medium {
 public:
  FormulaMedium(MediumInfo info, std::function<double(double)> n_of_lambda_um)
      : Medium(std::move(info)), n_(std::move(n_of_lambda_um)) {}

 protected:
  std::complex<double> index_in_range(double lambda_nm, double) const override {
    return {n_(lambda_nm * 1e-3), 0.0};
  }

 private:
  std::function<double(double)> n_;
};

// Sellmeier form n^2 = 1 + sum_i B_i lambda^2 / (lambda^2 - C_i), lambda in micrometres,
// C_i in micrometres squared.
std::function<double(double)> sellmeier(std::vector<std::array<double, 2>> terms) {
  return [terms = std::move(terms)](double l) {
    const double l2 = l * l;
    double n2 = 1;
    for (const auto& [b, c] : terms) n2 += b * l2 / (l2 - c);
    return std::sqrt(n2);
  };
}

// Ciddor (1996) standard air, n - 1 = 0.05792105 / (238.0185 - l^-2) + 0.00167917 / (57.362 - l^-2),
// l the vacuum wavelength in micrometres.
double ciddor_standard_air(double l) {
  const double s2 = 1 / (l * l);
  return 1 + 0.05792105 / (238.0185 - s2) + 0.00167917 / (57.362 - s2);
}

// Glass catalogues and most dispersion fits give the index relative to air at air wavelengths.
// hydrolux uses absolute indices at vacuum wavelengths (as IAPWS R9-97 does), so such a formula
// n_rel(l_air) becomes n(l_vac) = n_air(l_vac) * n_rel(l_vac / n_air(l_vac)), with Ciddor's air.
std::function<double(double)> made_absolute(std::function<double(double)> relative_to_air) {
  return [rel = std::move(relative_to_air)](double l) {
    const double n_air = ciddor_standard_air(l);
    return n_air * rel(l / n_air);
  };
}

class ConstantMedium final : public Medium {
 public:
  explicit ConstantMedium(std::complex<double> index)
      : Medium(MediumInfo{fmt::format("const:{:g}{}", index.real(),
                                      index.imag() > 0 ? fmt::format("+{:g}i", index.imag()) : ""),
                          "constant index", "user-given constant", 0.0,
                          std::numeric_limits<double>::max(), false, -273.15, 1e9, 20.0,
                          index.imag() > 0}),
        index_(index) {}

 protected:
  std::complex<double> index_in_range(double, double) const override { return index_; }

 private:
  std::complex<double> index_;
};

// ---------------------------------------------------------------------------------------------
// Water: real part from IAPWS R9-97, imaginary part from Hale & Querry (1973).

class WaterMedium final : public Medium {
 public:
  WaterMedium(MediumInfo info, std::shared_ptr<const NkTable> k_table)
      : Medium(std::move(info)), k_table_(std::move(k_table)) {}

 protected:
  std::complex<double> index_in_range(double lambda_nm, double temperature_c) const override {
    const double n =
        iapws_water_index(lambda_nm, temperature_c + 273.15, water_density_kg_m3(temperature_c));
    return {n, k_table_->interpolate_k(lambda_nm)};
  }

 private:
  std::shared_ptr<const NkTable> k_table_;
};

const char* const kIapwsSource =
    "IAPWS R9-97, Harvey, Gallagher & Levelt Sengers, J. Phys. Chem. Ref. Data 27, 761 (1998); "
    "k: Hale & Querry, Appl. Opt. 12, 555 (1973)";

struct Registry {
  std::vector<std::shared_ptr<const Medium>> media;
  std::map<std::string, std::shared_ptr<const Medium>, std::less<>> by_name;

  void add(std::shared_ptr<const Medium> m, std::initializer_list<const char*> aliases = {}) {
    by_name.emplace(m->info().name, m);
    for (const char* a : aliases) by_name.emplace(a, m);
    media.push_back(std::move(m));
  }
};

// A medium's name, description, source and valid range of vacuum wavelengths.
MediumInfo medium_info(std::string name, std::string description, std::string source, double lambda_min_nm,
                       double lambda_max_nm) {
  MediumInfo info;
  info.name = std::move(name);
  info.description = std::move(description);
  info.source = std::move(source);
  info.lambda_min_nm = lambda_min_nm;
  info.lambda_max_nm = lambda_max_nm;
  return info;
}

std::shared_ptr<const Medium> tabulated(const char* name, const char* description,
                                        const char* path, bool conductor) {
  auto table = std::make_shared<const NkTable>(path);
  MediumInfo info = medium_info(name, description, table->table.meta_or_empty("source"), table->lambda.front(),
                                table->lambda.back());
  info.conductor = conductor;
  return std::make_shared<TabulatedMedium>(std::move(info), std::move(table));
}

const Registry& registry() {
  static const Registry r = [] {
    Registry reg;
    {
      // 200-1100 nm: IAPWS R9-97 range 0.2-1.1 um; Hale & Querry starts at 200 nm
      MediumInfo info = medium_info("water", "liquid water (n: IAPWS R9-97 at 0.1 MPa; k: Hale & Querry 1973, 25 C)",
                                    kIapwsSource, 200, 1100);
      info.temperature_dependent = true;
      info.temperature_min_c = 0;  // range of the density formula at 0.1 MPa (liquid)
      info.temperature_max_c = 100;
      info.default_temperature_c = 20;
      reg.add(std::make_shared<WaterMedium>(
                  std::move(info), std::make_shared<const NkTable>("media/water_hale_querry_1973.csv")),
              {"liquid-water"});
    }
    {
      auto ice = tabulated("ice", "ice Ih at -7 C", "media/ice_warren_brandt_2008.csv", false);
      auto info = ice->info();
      info.temperature_min_c = info.temperature_max_c = info.default_temperature_c = -7;
      reg.add(std::make_shared<TabulatedMedium>(
          info, std::make_shared<const NkTable>("media/ice_warren_brandt_2008.csv")));
    }
    {
      const MediumInfo info = medium_info(
          "pmma", "PMMA (acrylic, poly(methyl methacrylate)), 20 C",
          "Sultanova, Kasarova & Nikolov, Acta Phys. Pol. A 116, 585 (2009), one-term Sellmeier fit "
          "of their data by refractiveindex.info",
          436.8, 1052);
      reg.add(std::make_shared<FormulaMedium>(info, made_absolute(sellmeier({{{1.1819, 0.011313}}}))),
              {"acrylic"});
    }
    {
      const MediumInfo info = medium_info("bk7", "Schott N-BK7 borosilicate crown glass, 20 C",
                                          "SCHOTT N-BK7 Sellmeier coefficients (catalogue 2017)", 300, 2500);
      reg.add(std::make_shared<FormulaMedium>(
                  info, made_absolute(sellmeier({{1.03961212, 0.00600069867},
                                                 {0.231792344, 0.0200179144},
                                                 {1.01046945, 103.560653}}))),
              {"glass"});
    }
    {
      const MediumInfo info = medium_info("fused-silica", "fused silica (amorphous SiO2), 20 C",
                                          "Malitson, J. Opt. Soc. Am. 55, 1205 (1965)", 210, 3710);  // relative to air
      reg.add(std::make_shared<FormulaMedium>(
          info, made_absolute(sellmeier({{0.6961663, 0.0684043 * 0.0684043},
                                         {0.4079426, 0.1162414 * 0.1162414},
                                         {0.8974794, 9.896161 * 9.896161}}))));
    }
    {
      MediumInfo info = medium_info("air", "standard air: 15 C, 101325 Pa, dry, 450 ppm CO2",
                                    "Ciddor, Appl. Opt. 35, 1566 (1996)", 230, 1690);
      info.temperature_min_c = info.temperature_max_c = info.default_temperature_c = 15;
      reg.add(std::make_shared<FormulaMedium>(info, ciddor_standard_air));
    }
    reg.add(tabulated("gold", "gold (evaporated film, room temperature)",
                      "media/gold_johnson_christy_1972.csv", true));
    reg.add(tabulated("silver", "silver (evaporated film, room temperature)",
                      "media/silver_johnson_christy_1972.csv", true));
    reg.add(tabulated("copper", "copper (evaporated film, room temperature)",
                      "media/copper_johnson_christy_1972.csv", true));
    reg.add(tabulated("aluminium", "aluminium (evaporated film)",
                      "media/aluminium_rakic_1995.csv", true),
            {"aluminum"});
    return reg;
  }();
  return r;
}

std::optional<double> parse_double(std::string_view s) {
  double v = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

}  // namespace

std::shared_ptr<const Medium> constant_medium(std::complex<double> index) {
  if (!(index.real() > 0) || !std::isfinite(index.real()))
    throw UnknownNameError(fmt::format("constant medium: n = {:g} must be a finite number > 0", index.real()));
  if (!(index.imag() >= 0) || !std::isfinite(index.imag()))
    throw UnknownNameError(fmt::format("constant medium: k = {:g} must be a finite number >= 0", index.imag()));
  return std::make_shared<ConstantMedium>(index);
}

std::shared_ptr<const Medium> find_medium(std::string_view name) {
  constexpr std::string_view kConst = "const:";
  if (name.starts_with(kConst)) {
    std::string_view spec = name.substr(kConst.size());
    double k = 0;
    if (spec.ends_with('i')) {
      // The '+' between the parts: the last one that is not an exponent's sign.
      auto plus = spec.rfind('+');
      while (plus != std::string_view::npos && plus > 0 && (spec[plus - 1] == 'e' || spec[plus - 1] == 'E'))
        plus = plus == 1 ? std::string_view::npos : spec.rfind('+', plus - 1);
      const auto kv = plus == std::string_view::npos
                          ? std::nullopt
                          : parse_double(spec.substr(plus + 1, spec.size() - plus - 2));
      if (!kv)
        throw UnknownNameError(fmt::format(
            "medium '{}': expected const:<n> or const:<n>+<k>i, e.g. const:1.49 or const:0.2+3.4i",
            name));
      k = *kv;
      spec = spec.substr(0, plus);
    }
    const auto n = parse_double(spec);
    if (!n)
      throw UnknownNameError(fmt::format(
          "medium '{}': expected const:<n> or const:<n>+<k>i, e.g. const:1.49 or const:0.2+3.4i",
          name));
    return constant_medium({*n, k});
  }
  const auto& reg = registry();
  if (const auto it = reg.by_name.find(name); it != reg.by_name.end()) return it->second;
  throw UnknownNameError(fmt::format("unknown medium '{}'; valid: {}, or const:<n>[+<k>i]", name,
                                     fmt::join(medium_names(), ", ")));
}

std::vector<std::string> medium_names() {
  std::vector<std::string> names;
  for (const auto& m : registry().media) names.push_back(m->info().name);
  return names;
}

// Density of air-free liquid water at 0.101325 MPa: Kell, J. Chem. Eng. Data 20, 97 (1975),
// eq. 16 (rational fit, 0-150 C), t in Celsius (IPTS-68; the difference to ITS-90 is below the fit's
// uncertainty here).
double water_density_kg_m3(double t) {
  const double num = 999.83952 + t * (16.945176 + t * (-7.9870401e-3 +
                                 t * (-46.170461e-6 + t * (105.56302e-9 + t * -280.54253e-12))));
  return num / (1 + 16.879850e-3 * t);
}

// IAPWS R9-97, eq. (1) and Table 1: the Lorentz-Lorenz function of the reduced density, temperature
// and wavelength.
double iapws_water_index(double lambda_nm, double temperature_k, double density_kg_m3) {
  constexpr double a0 = 0.244257733, a1 = 9.74634476e-3, a2 = -3.73234996e-3, a3 = 2.68678472e-4,
                   a4 = 1.58920570e-3, a5 = 2.45934259e-3, a6 = 0.900704920, a7 = -1.66626219e-2;
  constexpr double lambda_uv = 0.2292020, lambda_ir = 5.432937;  // reduced
  constexpr double t_ref = 273.15, rho_ref = 1000.0, lambda_ref_nm = 589.0;
  const double rho = density_kg_m3 / rho_ref;
  const double t = temperature_k / t_ref;
  const double l = lambda_nm / lambda_ref_nm;
  const double l2 = l * l;
  const double rhs = a0 + a1 * rho + a2 * t + a3 * l2 * t + a4 / l2 + a5 / (l2 - lambda_uv * lambda_uv) +
                     a6 / (l2 - lambda_ir * lambda_ir) + a7 * rho * rho;
  const double ll = rho * rhs;  // (n^2 - 1) / (n^2 + 2)
  return std::sqrt((1 + 2 * ll) / (1 - ll));
}

}  // namespace hydrolux::optics
