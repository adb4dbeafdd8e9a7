// One sphere's Lorenz-Mie solution: see hydrolux/scatter/mie_solution.hpp.
#include "hydrolux/scatter/mie_solution.hpp"

#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"

namespace hydrolux::scatter {

MieSolution solve_mie(Complex m, double x, std::span<const double> mu, std::optional<int> debye, int threads,
                      const ProgressFn& progress) {
  MieSolution r;
  if (mu.empty()) {
    r.terms = mie_terms(x);
    r.q = mie_efficiencies(m, x);
    return r;
  }
  const MieCoefficients c = mie_coefficients(m, x);
  r.terms = c.terms();
  r.q = mie_efficiencies(c);  // of the whole sphere, also with a Debye order
  r.s1.resize(mu.size());
  r.s2.resize(mu.size());
  mie_amplitudes(debye ? debye_coefficients(m, x, *debye) : c, mu, r.s1, r.s2, threads, progress);
  return r;
}

}  // namespace hydrolux::scatter
