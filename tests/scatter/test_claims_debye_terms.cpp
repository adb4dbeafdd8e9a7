// Claims of docs/debye.md about the closed form (D2) and the single orders (D6, D7), checked
// against partial-wave Fresnel coefficients built in this file from Riccati-Hankel functions by
// their own upward recurrence in long double (not through scatter/debye.hpp), and against the Mie
// coefficients of scatter/mie.hpp (a different algorithm: the logarithmic derivative D_n(m x)
// downward, no Hankel function of the complex argument).
//
// Conventions (Bohren & Huffman 1983, section 4.8; debye.hpp's header), written out here:
//   xi1 = psi - i chi (outgoing): xi1_{-1} = e^{iz},  xi1_0 = -i e^{iz}
//   xi2 = psi + i chi (incoming): xi2_{-1} = e^{-iz}, xi2_0 =  i e^{-iz}
//   xi_{n+1} = (2n + 1)/z xi_n - xi_{n-1},  xi_n' = xi_{n-1} - n xi_n / z
// (Hankel functions are never the minimal solution of the recurrence, so upward is stable), and
// after Hovenac & Lock, J. Opt. Soc. Am. A 9, 781 (1992), with z = m x, kappa = 1/m (a_n) or m (b_n):
//   R22 = -[xi2(x)/xi1(x)] [D2(x) - kappa D2(z)] / [D1(x) - kappa D2(z)]
//   R11 = -[xi1(z)/xi2(z)] [kappa D1(z) - D1(x)] / [kappa D2(z) - D1(x)]
//   T21 T12 = -4 kappa / {xi1(x)^2 xi2(z)^2 [D1(x) - kappa D2(z)]^2}
// The Debye orders are a^(0) = (1 - R22) / 2 and a^(p) = -T21 T12 R11^(p-1) / 2 (p >= 1), and their
// sum, (D2): a = [1 - R22 - T21 T12 / (1 - R11)] / 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <vector>

#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/mie.hpp"

namespace hydrolux::scatter {
namespace {

using LC = std::complex<long double>;

struct Hankel {
  std::vector<LC> xi, d;  // xi_n and its log derivative xi_n'/xi_n, n = 1..N at n - 1
};

Hankel riccati_hankel(LC z, int n_max, bool outgoing) {
  const LC i(0, 1);
  const LC e = outgoing ? std::exp(i * z) : std::exp(-i * z);
  LC below = e;                        // n = -1
  LC here = outgoing ? -i * e : i * e;  // n = 0
  Hankel h;
  for (int n = 0; n < n_max; ++n) {
    const LC above = static_cast<long double>(2 * n + 1) / z * here - below;
    below = here;
    here = above;
    h.xi.push_back(here);
    h.d.push_back((below - static_cast<long double>(n + 1) * here / z) / here);
  }
  return h;
}

// R22, R11 and T21 T12 of one polarisation, n = 1..N.
struct Fresnel {
  std::vector<LC> r22, r11, tt;
};

Fresnel fresnel(std::complex<double> m_d, double x_d, int n_max, bool is_a) {
  const LC m(m_d.real(), m_d.imag());
  const LC x(x_d, 0);
  const LC z = m * x;
  const LC kappa = is_a ? LC(1) / m : m;
  const Hankel o_x = riccati_hankel(x, n_max, true), i_x = riccati_hankel(x, n_max, false);
  const Hankel o_z = riccati_hankel(z, n_max, true), i_z = riccati_hankel(z, n_max, false);
  Fresnel f;
  for (std::size_t k = 0; k < static_cast<std::size_t>(n_max); ++k) {
    const LC den = o_x.d[k] - kappa * i_z.d[k];
    f.r22.push_back(-(i_x.xi[k] / o_x.xi[k]) * (i_x.d[k] - kappa * i_z.d[k]) / den);
    f.r11.push_back(-(o_z.xi[k] / i_z.xi[k]) * (kappa * o_z.d[k] - o_x.d[k]) /
                    (kappa * i_z.d[k] - o_x.d[k]));
    f.tt.push_back(LC(-4) * kappa / (o_x.xi[k] * o_x.xi[k] * i_z.xi[k] * i_z.xi[k] * den * den));
  }
  return f;
}

std::complex<double> to_d(LC c) {
  return {static_cast<double>(c.real()), static_cast<double>(c.imag())};
}

// Water without and with absorption, and a glass-like index; sizes where the test's long-double
// recurrences keep ~1e-14 of R22, R11 (they lose a few digits to cancellation below x ~ 1).
struct Case {
  std::complex<double> m;
  double x;
};
const Case kCases[] = {{{1.333, 0.0}, 5.0},   {{1.333, 0.0}, 60.0},  {{1.333, 0.01}, 30.0},
                       {{1.5, 0.1}, 12.0},   {{1.333, 1e-3}, 150.0}, {{0.75, 0.0}, 20.0}};

// docs/debye.md l. 107-109: the literal (D2), 1/2 [1 - R22 - T21 T12 / (1 - R11)], built from R22,
// R11 and T21 T12 agrees with the forms that do not cancel where it is well conditioned. Here the
// literal form is built from this file's R22, R11, T21 T12 and compared with (i) the Mie
// coefficients (a different algorithm) and (ii) the library's 1 - R22 (D3') and T21 T12 / (1 - R11)
// (D5'). Well conditioned: abs(1 - R11) >= 1e-3 (else the division amplifies the rounding of R11 a
// thousandfold) and n below x (past the edge R22 and R11 are 1 to within the digits kept).
// Tolerance 1e-11 of the largest of the terms (1, abs(T21 T12 / (1 - R11))): double rounding of
// O(1) quantities times the few hundred ulp the recurrences to n ~ 150 lose.
TEST(ClaimsDebyeTerms, LiteralClosedFormFromIndependentFresnelCoefficientsEqualsMie) {
  for (const Case& c : kCases) {
    const MieCoefficients mie = mie_coefficients(c.m, c.x);
    const DebyeInterface lib = debye_interface(c.m, c.x);
    const int n_terms = mie.terms();
    ASSERT_EQ(lib.terms(), n_terms);
    for (const bool is_a : {true, false}) {
      const Fresnel f = fresnel(c.m, c.x, n_terms, is_a);
      const DebyeFresnel& lf = is_a ? lib.a : lib.b;
      int checked = 0;
      for (int n = 1; n < c.x; ++n) {
        const auto k = static_cast<std::size_t>(n - 1);
        const LC one_minus_r11 = LC(1) - f.r11[k];
        if (std::abs(one_minus_r11) < 1e-3L) continue;
        const LC transmitted = f.tt[k] / one_minus_r11;
        const std::complex<double> literal = to_d(LC(0.5) * (LC(1) - f.r22[k] - transmitted));
        const double scale = std::max(1.0, static_cast<double>(std::abs(transmitted)));
        const std::complex<double> ref = is_a ? mie.a[k] : mie.b[k];
        EXPECT_LT(std::abs(literal - ref) / scale, 1e-11)
            << "m " << c.m << " x " << c.x << " n " << n << (is_a ? " a" : " b");
        // The library's non-cancelling forms (D3'), (D5') against the literal ones built here.
        EXPECT_LT(std::abs(lf.one_minus_r22[k] - to_d(LC(1) - f.r22[k])), 1e-11) << "n " << n;
        EXPECT_LT(std::abs(lf.transmitted[k] - to_d(transmitted)) / scale, 1e-11) << "n " << n;
        ++checked;
      }
      EXPECT_GT(checked, 0.8 * (c.x - 1)) << "m " << c.m << " x " << c.x;
    }
  }
}

// docs/debye.md l. 111-113: a single order is the term of the series, p = 0 is (1 - R22) / 2 and
// p >= 1 is -T21 T12 R11^(p-1) / 2; a range of orders is the sum of its terms, and all orders
// 0..P plus the remainder are the Mie coefficient. The terms are built here from this file's
// R22, R11, T21 T12; the library's single orders, its ranges (`debye_orders`) and its sums plus
// remainders are compared with them, and the last with `mie_coefficients`. Every n up to the
// truncation is compared (absolute 1e-11: the terms are at most ~1 for these indices, and the
// recurrences' rounding is below that); relative 1e-9 where a term is above 1e-6.
TEST(ClaimsDebyeTerms, SingleOrdersAreTheTermsOfIndependentFresnelCoefficients) {
  const int p_max = 6;
  for (const Case& c : kCases) {
    const DebyeInterface lib = debye_interface(c.m, c.x);
    const MieCoefficients mie = mie_coefficients(c.m, c.x);
    const int n_terms = lib.terms();
    std::vector<MieCoefficients> order;
    for (int p = 0; p <= p_max; ++p) order.push_back(debye_coefficients(lib, p));
    const MieCoefficients range_2_5 = debye_orders(lib, 2, 5);
    for (const bool is_a : {true, false}) {
      const Fresnel f = fresnel(c.m, c.x, n_terms, is_a);
      for (int n = 1; n <= n_terms; ++n) {
        const auto k = static_cast<std::size_t>(n - 1);
        LC term = LC(0.5) * (LC(1) - f.r22[k]);
        LC range = 0;
        for (int p = 0; p <= p_max; ++p) {
          if (p >= 1) term = (p == 1) ? LC(-0.5) * f.tt[k] : term * f.r11[k];
          const std::complex<double> lib_term = is_a ? order[static_cast<std::size_t>(p)].a[k]
                                                     : order[static_cast<std::size_t>(p)].b[k];
          const double err = std::abs(lib_term - to_d(term));
          EXPECT_LT(err, 1e-11) << "m " << c.m << " x " << c.x << " n " << n << " p " << p;
          if (std::abs(term) > 1e-6L) {
            EXPECT_LT(err / static_cast<double>(std::abs(term)), 1e-9) << "n " << n << " p " << p;
          }
          if (p >= 2 && p <= 5) range += term;
        }
        const std::complex<double> lib_range = is_a ? range_2_5.a[k] : range_2_5.b[k];
        EXPECT_LT(std::abs(lib_range - to_d(range)), 1e-11) << "n " << n;
      }
    }
    // The orders 0..P and everything beyond them, summed by the library, against Mie.
    for (const int p : {0, 2, 5}) {
      const MieCoefficients sum = debye_orders(lib, 0, p);
      const MieCoefficients rest = debye_remainder(lib, p);
      for (std::size_t k = 0; k < mie.a.size(); ++k) {
        EXPECT_LT(std::abs(sum.a[k] + rest.a[k] - mie.a[k]), 1e-11) << "x " << c.x << " P " << p;
        EXPECT_LT(std::abs(sum.b[k] + rest.b[k] - mie.b[k]), 1e-11) << "x " << c.x << " P " << p;
      }
    }
  }
}

}  // namespace
}  // namespace hydrolux::scatter
