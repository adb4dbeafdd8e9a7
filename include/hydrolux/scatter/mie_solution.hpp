#pragma once
// One sphere's Lorenz-Mie solution as `hydrolux mie` computes it (io/mie_job.hpp writes it out): the
// number of terms, the efficiencies of the whole sphere and, at the given angles, the amplitudes S1, S2
// of the whole sphere or of one Debye order alone.
#include <optional>
#include <span>
#include <vector>

#include "hydrolux/core/progress.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {

struct MieSolution {
  int terms = 0;                 // the partial waves summed (mie_terms(x))
  MieEfficiencies q;             // of the whole sphere, also with a Debye order
  std::vector<Complex> s1, s2;   // one per mu; empty without angles
};

// The sphere of index `m` and size parameter `x`. With no `mu` (cosines of the scattering angles), the
// efficiencies alone (mie_efficiencies(m, x)); else the coefficients once, their efficiencies, and the
// amplitudes at every mu through mie_amplitudes (`threads`, `progress`) of the whole sphere or, with
// `debye`, of that Debye order's coefficients (debye_coefficients). DomainError outside the solver's
// domain (mie.hpp: "x", "m_real", ...).
MieSolution solve_mie(Complex m, double x, std::span<const double> mu, std::optional<int> debye = {},
                      int threads = 0, const ProgressFn& progress = {});

}  // namespace hydrolux::scatter
