#pragma once
// Airy theory of the rainbow of order p (p = 2 primary, p = 3 secondary), both polarisations, in
// the Bohren & Huffman normalisation of hydrolux/scatter/mie.hpp, and the Airy function Ai.
// The derivation is in docs/rainbow-theories.md.
//
// References:
// - G. B. Airy, Trans. Camb. Phil. Soc. 6, 379 (1838); van de Hulst, "Light Scattering by Small
//   Particles" (1957), sections 13.21-13.23 (the cubic wavefront, the h parameter, the shift of
//   the maximum and the supernumeraries).
// - G. P. Konnen and J. H. de Boer, Appl. Opt. 18, 1961 (1979): Airy theory per polarisation, the
//   Fresnel factors taken at the rainbow ray.
// - R. T. Wang and H. C. van de Hulst, Appl. Opt. 30, 106 (1991): Airy against Mie for rainbows.
// - R. L. Lee, Appl. Opt. 37, 5221 (1998): Airy and Mie Lee diagrams of the natural rainbow.
// - Abramowitz & Stegun, Handbook of Mathematical Functions (1964), section 10.4 (Ai).
//
// The amplitude near the rainbow angle theta_R (geometric.hpp's RainbowRay: rainbow ray theta_i,
// impact parameter b_R, side sigma, curvature q = (1/2) d^2 Theta/db^2), per polarisation j:
//     S_j(theta) = eps_j sqrt(2 pi b_R / sin theta_R) x^(7/6) q^(-1/3) Ai(-z)
//                  * exp(i [delta_R + x b_R dTheta - pi (N + 1) / 2 - pi / 4])
//     dTheta = sigma (theta - theta_R),   z = x^(2/3) q^(-1/3) dTheta,
// where eps_j are the Fresnel factors of order p at the rainbow ray (geometric.hpp), delta_R =
// 2 x (p n cos theta_t - cos theta_i) its optical path, and N the focal lines of the rays on the
// branch theta_i < theta_i,R. It is fixed by matching, on the lit side (z >> 1), the two
// geometric-optics rays of geometric.hpp: same magnitudes, same phase difference 2 zeta = (4/3)
// z^(3/2), same mean phase, to leading order in the distance from the rainbow ray. The intensity
// peaks at z = 1.0188 (first zero of Ai'), inside the geometric bow by 1.0188 q^(1/3) x^(-2/3) rad.
//
// Validity: x >> 1 (x >= ~1000 for rainbows of rain drops) and |theta - theta_R| small enough for
// the cubic wavefront, in practice a few degrees around the bow (|z| up to ~10-20 for x ~ 1e3-1e4);
// the absolute phase is good only for z^2 << x^(1/3). Airy theory has no p != order terms, no
// diffraction, and the parallel polarisation is least accurate (its Fresnel factor varies fast near
// Brewster's angle, which the primary rainbow ray is close to); see Wang & van de Hulst (1991).
#include <complex>
#include <span>

#include "hydrolux/scatter/geometric.hpp"

namespace hydrolux::scatter {

// The Airy function Ai(x) and its derivative Ai'(x), for any finite real x:
// |x| <= 2: Maclaurin series Ai = c1 f - c2 g (A&S 10.4.2-10.4.5);
// x > 2: Ai(x) = (1/pi) sqrt(x/3) K_{1/3}(zeta), Ai'(x) = -(x / (pi sqrt 3)) K_{2/3}(zeta);
// x = -z < -2: Ai(-z) = (sqrt z / 2) (J_{1/3}(zeta) - Y_{1/3}(zeta) / sqrt 3),
//              Ai'(-z) = (z / 2) (J_{2/3}(zeta) + Y_{2/3}(zeta) / sqrt 3),
// zeta = (2/3) |x|^(3/2) (A&S 10.4.14-10.4.17 with Y_nu written for J_{-nu}), through
// std::cyl_bessel_k / cyl_bessel_j / cyl_neumann. Ai underflows to 0 beyond x ~ 104.
double airy_ai(double x);
double airy_ai_prime(double x);

// Ai(x) from a table of Ai and Ai' (every 1/128 on [-16, 12], cubic Hermite) and the asymptotic
// expansion below -16 (A&S 10.4.60, four terms); 0 above 12. Within 1e-8 of airy_ai everywhere
// (tests/scatter/test_airy.cpp) at ~10 ns a call, against ~1 us for the Bessel functions: for
// tables that evaluate it millions of times.
double airy_ai_fast(double x);

// The rainbow's Airy scale: z per radian of scattering angle, x^(2/3) q^(-1/3) (always > 0; the
// side sign is in RainbowRay::side).
double airy_angular_scale(double n, double x, int p);

// The Airy argument z at theta (radians): sigma (theta - theta_R) x^(2/3) q^(-1/3); z > 0 on the
// lit side.
double airy_argument(double n, double x, int p, double theta);

// The constants of one rainbow (order p, real index n, size parameter x) in the amplitude above.
struct AiryRainbow {
  RainbowRay ray;
  double x = 0;
  RayFresnelFactors eps;  // at the rainbow ray
  double scale = 0;       // z per radian, x^(2/3) q^(-1/3)
  double amplitude = 0;   // sqrt(2 pi b_R / sin theta_R) x^(7/6) q^(-1/3)
  double phase0 = 0;      // delta_R - pi (N + 1) / 2 - pi / 4
};
// kappa = Im m >= 0 (at most 1) attenuates the amplitude by exp(-2 p x kappa cos theta_t,R), the
// rainbow ray's p chords through a weakly absorbing drop (van de Hulst 1957 section 14.2).
AiryRainbow airy_rainbow(double n_real, double x, int p, double kappa = 0);

// The unpolarised intensity (|S1|^2 + |S2|^2) / 2 at theta (radians) through airy_ai_fast:
// (|eps_1|^2 + |eps_2|^2) / 2 * amplitude^2 * Ai(-z)^2.
double airy_intensity(const AiryRainbow& a, double theta);

// Airy amplitudes of order p >= 2 at each theta (radians, [0, pi]; s1, s2 the size of theta_rad),
// for a real index 1 < n_real < p. Evaluated at any angle, meaningful near theta_R (see above).
void airy_amplitudes(double n_real, double x, int p, std::span<const double> theta_rad,
                     std::span<Complex> s1, std::span<Complex> s2);

}  // namespace hydrolux::scatter
