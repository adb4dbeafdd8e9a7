#pragma once
// One entry point for the single-drop theories, so callers (the CLI, LUT builders) choose one by
// name: Lorenz-Mie (exact), one Debye order (exact, one path class), Airy theory of the rainbow
// (approximate, near a rainbow) and geometric optics with interference (approximate, large x).
// All return S1, S2 in the normalisation of mie.hpp, so their intensities compare directly.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/core/progress.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/size_distribution.hpp"

namespace hydrolux::scatter {

enum class TheoryKind { Mie, Debye, Airy, Geometric };

struct Theory {
  TheoryKind kind = TheoryKind::Mie;
  int p = 0;  // Debye: the order; Airy: the rainbow order (2 primary, 3 secondary); geometric:
              // the highest ray order summed (0..p)
};

// "mie", "debye:P" (P in 0..1000), "airy" (= airy:2), "airy:P" (P in 2..20), "geometric"
// (= geometric:3: orders 0..3 plus Fraunhofer diffraction), "geometric:P" (P in 0..50).
// Throws UnknownNameError (bad name) or DomainError ("p", bad order).
Theory parse_theory(std::string_view text);
std::string theory_name(const Theory& t);

// S1, S2 at the scattering angles theta_rad (radians, 0 forward) for relative index m and size
// parameter x. threads: 0 = all cores (Mie and Debye; the approximations are single-threaded).
// Airy theory is meaningful near its rainbow angle (airy.hpp) and needs 1 < Re m < p.
void amplitudes(const Theory& t, Complex m, double x, std::span<const double> theta_rad,
                std::span<Complex> s1, std::span<Complex> s2, int threads = 0);

// A Gauss-Legendre quadrature in ln r over the radii of a gamma or log-normal distribution that
// holds its r^2- to r^4-weighted mass (intensities grow like r^2 to r^4) to 1e-6: gamma from 1e-3
// of the mean (drops that small scatter ~ (1e-3)^6 as much; for relative width 1 they are 1e-3 of
// the number) to beta (alpha + 4 + 10 sqrt(alpha + 4)), log-normal from exp(mu - 8 s) to
// exp(mu + 4 s^2 + 8 s).
// Monodisperse gives its one radius. (Marshall-Palmer rain is usually cut to physical radii: use
// SizeDistribution::quadrature(nodes, r_min, r_max).)
RadiusQuadrature intensity_quadrature(const SizeDistribution& d, int nodes);

// Intensities i1 = |S1|^2 and i2 = |S2|^2 averaged over the drops of a size distribution: the
// number-weighted mean over the quadrature's radii, each drop solved at its own size parameter
// (B&H normalisation, so i / k^2 is the intensity per drop per unit incident irradiance at unit
// distance). Oscillating theories (Mie, Debye) need nodes that resolve the ripple in r, about
// lambda / 10 apart; `progress` is called after each radius. s2_s1conj is the same mean of the
// product S2 S1*, whose real and imaginary parts are the Mueller elements S33 and S34 (mueller.hpp).
struct Intensities {
  std::vector<double> i1, i2;
  std::vector<Complex> s2_s1conj;
};
Intensities average_intensities(const Theory& t, const RadiusQuadrature& q, double wavelength_nm,
                                const optics::Medium& drop, const optics::Medium& surrounding,
                                std::optional<double> temperature_c, std::span<const double> theta_rad,
                                int threads = 0, const ProgressFn& progress = {});

}  // namespace hydrolux::scatter
