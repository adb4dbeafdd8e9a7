#pragma once
// Lorenz-Mie results as a labelled dataset with CF-1.8 attributes (core/dataset.hpp): what
// `hydrolux mie -o phase.nc` writes (through io/netcdf.hpp) and Python's MieResult.to_xarray()
// returns, from one description.
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "hydrolux/core/dataset.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/mueller.hpp"

namespace hydrolux::scatter {

struct MieDatasetInput {
  Complex m;                            // relative index
  std::span<const double> x;            // N size parameters
  std::span<const double> qext, qsca, qabs, qback, g;  // N each
  std::span<const int> n_terms;         // N
  std::span<const double> angles_deg;   // A angles; empty: the efficiencies alone
  std::span<const Complex> s1, s2;      // N x A, row-major (size parameter, angle)
  // N x A each with the Mueller elements (Bohren & Huffman eq. 4.77), else empty.
  std::span<const double> s11, s12, s33, s34;
  std::optional<int> debye_p;           // the amplitudes of one Debye order alone
  // The physical form, when the problem was posed as drops in a medium (else nullopt / empty).
  std::optional<double> wavelength_nm;
  std::span<const double> radius_um;    // N
  std::string medium, surrounding;
  std::optional<double> temperature_c;
};

// The input for one sphere: x, its efficiencies and its term count (spans over the arguments, which
// must outlive the input), the amplitudes S1, S2 at `angles_deg` and, if given, the Mueller elements.
MieDatasetInput one_sphere(Complex m, const double& x, const MieEfficiencies& q, const int& n_terms,
                           std::span<const double> angles_deg, std::span<const Complex> s1,
                           std::span<const Complex> s2, const MuellerElements* mueller);

// Dimensions size_parameter (N) and scattering_angle (A); coordinates size_parameter,
// scattering_angle (degree) and, in the physical form, radius (um); variables qext, qsca, qabs,
// qback, g, n_terms over size_parameter; s1_real, s1_imag, s2_real, s2_imag (and s11, s12, s33,
// s34) over (size_parameter, scattering_angle); phase_function, (|S1|^2 + |S2|^2) / 2 / (pi x^2
// Qsca), sr^-1, which integrates to 1 over the sphere (not with debye_p: one order's amplitudes are
// not normalised by the whole sphere's Qsca); the index and the medium as global attributes.
// Without angles, the efficiencies alone (no scattering_angle dimension). Error if the spans' sizes
// disagree, or if x or the angles (the coordinates) are not strictly increasing or strictly
// decreasing ("angles_deg: 10 is repeated ...": CF coordinates are strictly monotonic).
Dataset mie_dataset(const MieDatasetInput& in, std::string_view history);

}  // namespace hydrolux::scatter
