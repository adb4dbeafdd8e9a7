// Claims of docs/interface-optics.md and the metals_normal_incidence.svg caption checked against
// independent references: the Fresnel equations written out here in long double (Hecht 4.34,
// 4.40), Hale & Querry's published table, and the published positions of the metals' interband
// edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"

namespace hydrolux::optics {
namespace {

// Unpolarised reflectance from index n1 into n2 at cos_i in [0, 1], long double; 1 past the
// critical angle.
long double textbook_r(long double cos_i, long double n1, long double n2) {
  const long double s2 = (n1 / n2) * (n1 / n2) * (1 - cos_i * cos_i);
  if (s2 >= 1) return 1;
  const long double ct = std::sqrt(1 - s2);
  const long double rs = (n1 * cos_i - n2 * ct) / (n1 * cos_i + n2 * ct);
  const long double rp = (n2 * cos_i - n1 * ct) / (n2 * cos_i + n1 * ct);
  return (rs * rs + rp * rp) / 2;
}

// docs/interface-optics.md l. 37-39: fr_dielectric(cos, eta), the BSDFs' real-arithmetic path with
// a signed cosine (negative: light from inside, indices swapped), agrees with the Fresnel
// equations. Reference: the equations in long double, from both sides, including total internal
// reflection from inside, at 20001 angles. Within 2e-15 (a few ulp of R) except within 0.02 in cos
// of the critical angle, where R's slope in the angle is infinite and the rounding of cos i alone
// moves it: there within 1e-13 (measured 6e-14; the library's amplitude path fresnel_dielectric
// shows the same, 8e-14).
TEST(ClaimsInterface, FastFresnelPathMatchesTheTextbookEquations) {
  for (const double eta : {1.333, 1.5, 1 / 1.333, 2.4}) {
    const double n_dense = std::max(eta, 1 / eta);
    const double cos_crit = std::sqrt(1 - 1 / (n_dense * n_dense));
    for (int i = 0; i <= 20000; ++i) {
      const double c = std::cos(0.5 * std::numbers::pi * i / 20000.0);
      const double tol = std::abs(c - cos_crit) < 0.02 ? 1e-13 : 2e-15;
      EXPECT_NEAR(fr_dielectric(c, eta), static_cast<double>(textbook_r(c, 1, eta)), tol) << eta << " " << c;
      EXPECT_NEAR(fr_dielectric(-c, eta), static_cast<double>(textbook_r(c, eta, 1)), tol) << eta << " " << c;
    }
  }
}

// docs/interface-optics.md l. 49-50: water's k is Hale & Querry's (1973, 25 C), interpolated
// linearly in log k between their nodes. Published values (Appl. Opt. 12, 555, Table I) at nodes
// written here; between nodes the log-linear interpolation of those published values, written here
// (relative 1e-12).
TEST(ClaimsInterface, WaterAbsorptionIsHaleQuerryInterpolatedInLogK) {
  const auto water = find_medium("water");
  struct Node {
    double nm, k;
  };
  const Node table[] = {{200, 1.10e-7}, {250, 3.35e-8}, {300, 1.60e-8}, {350, 6.50e-9},
                        {400, 1.86e-9}, {450, 1.02e-9}, {500, 1.00e-9}, {550, 1.96e-9},
                        {575, 3.60e-9}, {600, 1.09e-8}, {650, 1.64e-8}, {700, 3.35e-8},
                        {725, 9.15e-8}, {750, 1.56e-7}, {800, 1.25e-7}, {850, 2.93e-7},
                        {900, 4.86e-7}, {925, 1.06e-6}, {950, 2.93e-6}, {1000, 2.89e-6}};
  for (const auto& n : table) EXPECT_NEAR(water->index(n.nm).imag(), n.k, 1e-12 * n.k) << n.nm;
  // Between published neighbours (25 nm apart): (lo, hi) and the fraction of the way.
  const struct {
    Node lo, hi;
    double f;
  } between[] = {{{550, 1.96e-9}, {575, 3.60e-9}, 0.5},  {{575, 3.60e-9}, {600, 1.09e-8}, 0.3},
                 {{700, 3.35e-8}, {725, 9.15e-8}, 0.8},  {{925, 1.06e-6}, {950, 2.93e-6}, 0.4}};
  for (const auto& b : between) {
    const double nm = b.lo.nm + b.f * (b.hi.nm - b.lo.nm);
    const double want = std::exp(std::log(b.lo.k) + b.f * (std::log(b.hi.k) - std::log(b.lo.k)));
    EXPECT_NEAR(water->index(nm).imag(), want, 1e-12 * want) << nm;
    // Not linear in k: at the midpoint of 575-600 nm linear would be 16% higher than log-linear.
  }
}

// Gallery metals_normal_incidence.svg (src/gallery/gallery.cpp:331): the figure plots
// R = ((n-1)^2 + k^2) / ((n+1)^2 + k^2) of the built-in metals. Copper reflects red better than
// blue: its d-band absorption edge lies near 2.1 eV (590 nm; Ehrenreich & Philipp, Phys. Rev. 128,
// 1622, 1962), so R rises steeply between 550 and 620 nm from about 0.6 in the blue to over 0.9 in
// the red. Aluminium dips near 800 nm: the interband transition near 1.5 eV (825 nm; Ehrenreich,
// Philipp & Segall, Phys. Rev. 132, 1918, 1963) gives a reflectance minimum of about 0.87 there,
// against above 0.9 through the visible.
TEST(ClaimsInterface, MetalsNormalIncidenceCaption) {
  const auto r_of = [](const Medium& m, double nm) {
    const std::complex<double> idx = m.index(nm);
    const double n = idx.real(), k = idx.imag();
    const double r = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    EXPECT_NEAR(fresnel_conductor(1.0, 1.0, idx).R, r, 1e-12) << m.info().name << " " << nm;
    return r;
  };
  const auto cu = find_medium("copper");
  EXPECT_LT(r_of(*cu, 450), 0.7);
  EXPECT_GT(r_of(*cu, 650), 0.9);
  double steepest = 0, at = 0;
  for (double nm = 450; nm < 700; nm += 5) {
    const double slope = r_of(*cu, nm + 5) - r_of(*cu, nm);
    if (slope > steepest) steepest = slope, at = nm + 2.5;
  }
  EXPECT_GT(at, 550);
  EXPECT_LT(at, 620);
  const auto al = find_medium("aluminium");
  double rmin = 1, where = 0;
  for (double nm = 400; nm <= 1000; nm += 2.5) {
    const double r = r_of(*al, nm);
    if (r < rmin) rmin = r, where = nm;
  }
  EXPECT_GT(where, 780);
  EXPECT_LT(where, 870);
  EXPECT_NEAR(rmin, 0.87, 0.02);
  EXPECT_GT(r_of(*al, 500), 0.9);
}

}  // namespace
}  // namespace hydrolux::optics
