#pragma once
// The Mueller (scattering) matrix of a sphere from its amplitudes S1 (perpendicular) and S2
// (parallel), in Bohren & Huffman's normalisation (1983, section 4.4.4, eq. 4.77):
//   S11 = (|S2|^2 + |S1|^2) / 2,   S12 = (|S2|^2 - |S1|^2) / 2,
//   S33 = Re(S2 S1*),               S34 = Im(S2 S1*),
// with S22 = S11, S44 = S33, S21 = S12, S43 = -S34 and the other elements zero. The signs are
// BHMIE's (B&H Appendix A: S34 = AIMAG(S2 * CONJG(S1))): S12 < 0 where light scattered from
// unpolarised light is polarised perpendicular to the scattering plane (Rayleigh's S12/S11 =
// -sin^2 / (1 + cos^2)), and the degree of linear polarisation is POL = -S12/S11. For one sphere
// S11^2 = S12^2 + S33^2 + S34^2; averages over sizes satisfy it only as an inequality (<=).
// Elements of S in the normalisation of mie.hpp: S11 / k^2 is the intensity scattered per unit
// incident irradiance at unit distance.
#include <span>
#include <vector>

#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/theories.hpp"

namespace hydrolux::scatter {

struct MuellerElement {
  double s11 = 0, s12 = 0, s33 = 0, s34 = 0;
};

// The four independent elements at one angle.
inline MuellerElement mueller_element(Complex s1, Complex s2) {
  const double i1 = std::norm(s1), i2 = std::norm(s2);
  const Complex c = s2 * std::conj(s1);
  return {0.5 * (i2 + i1), 0.5 * (i2 - i1), c.real(), c.imag()};
}

// The elements at each angle, from S1 and S2 (equal sizes, else std::invalid_argument).
struct MuellerElements {
  std::vector<double> s11, s12, s33, s34;
};
MuellerElements mueller_elements(std::span<const Complex> s1, std::span<const Complex> s2);

// The size-averaged elements, from average_intensities' number-weighted means of |S1|^2, |S2|^2
// and S2 S1* (theories.hpp): the average of each element over the drops.
MuellerElements mueller_elements(const Intensities& averaged);

}  // namespace hydrolux::scatter
