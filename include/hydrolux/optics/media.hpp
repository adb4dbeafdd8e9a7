#pragma once
// Optical media: complex refractive index n + i k as a function of vacuum wavelength (and, where
// the source models it, temperature). Indices are absolute (relative to vacuum): sources that give
// them relative to air (glass catalogues, BK7, fused silica, PMMA) are converted with Ciddor's
// standard air, a change of about 4e-4. Every medium names its source and its valid range; a
// wavelength or temperature outside it is a DomainError, never an extrapolation.
//
// Built-in media (names accepted by find_medium; aliases in brackets):
//   water [liquid-water]   n: IAPWS R9-97 (Harvey et al. 1998) at 0.1 MPa, 0-100 C, with Kell's
//                          (1975) density; k: Hale & Querry 1973 (25 C)
//   ice                    Warren & Brandt 2008 (ice Ih at -7 C), tabulated n and k
//   pmma [acrylic]         Sultanova et al. 2009 (436.8-1052 nm)
//   bk7 [glass]            Schott N-BK7 Sellmeier
//   fused-silica           Malitson 1965 Sellmeier
//   air                    Ciddor 1996 (standard air, 15 C, 101325 Pa, 450 ppm CO2)
//   gold, silver, copper   Johnson & Christy 1972, tabulated n and k
//   aluminium [aluminum]   Rakic 1995, tabulated n and k
//   const:<n> or const:<n>+<k>i   a constant index, valid at every wavelength
#include <complex>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hydrolux::optics {

struct MediumInfo {
  std::string name;         // canonical name, e.g. "water"
  std::string description;  // e.g. "liquid water"
  std::string source;       // citation(s) of the data or formula
  double lambda_min_nm = 0;  // valid vacuum-wavelength range, inclusive
  double lambda_max_nm = 0;
  bool temperature_dependent = false;
  // Valid temperature range (temperature-dependent media), or the temperature the data were
  // measured at (both ends equal) for the others.
  double temperature_min_c = 20;
  double temperature_max_c = 20;
  double default_temperature_c = 20;
  bool conductor = false;  // metals: k is large and light does not propagate inside
};

class Medium {
 public:
  virtual ~Medium() = default;
  const MediumInfo& info() const noexcept { return info_; }

  // Complex index n + i k at vacuum wavelength lambda_nm and temperature (Celsius). Without a
  // temperature, the medium's default is used. Throws DomainError ("wavelength_nm" or
  // "temperature_c") outside the valid ranges, and for a temperature given to a medium whose source
  // has no temperature model, unless it equals the data's own temperature.
  std::complex<double> index(double lambda_nm, std::optional<double> temperature_c = {}) const;
  double n(double lambda_nm, std::optional<double> temperature_c = {}) const {
    return index(lambda_nm, temperature_c).real();
  }

 protected:
  explicit Medium(MediumInfo info) : info_(std::move(info)) {}
  // Called with arguments already checked against info().
  virtual std::complex<double> index_in_range(double lambda_nm, double temperature_c) const = 0;

 private:
  MediumInfo info_;
};

// The medium called `name` (case-sensitive, aliases accepted, "const:..." builds a constant one).
// Throws UnknownNameError listing the valid names.
std::shared_ptr<const Medium> find_medium(std::string_view name);

// Canonical names of the built-in media, in a stable order.
std::vector<std::string> medium_names();

// A medium of constant complex index (real part > 0, imaginary part >= 0), valid at all wavelengths.
std::shared_ptr<const Medium> constant_medium(std::complex<double> index);

// Density of liquid water at 0.1 MPa, kg/m^3 (the formula cited in media.cpp), t in Celsius within
// the water medium's temperature range.
double water_density_kg_m3(double temperature_c);

// IAPWS R9-97 refractive index of water at density rho (kg/m^3), temperature T (K) and vacuum
// wavelength (nm), exposed for tests against the release's check values.
double iapws_water_index(double lambda_nm, double temperature_k, double density_kg_m3);

}  // namespace hydrolux::optics
