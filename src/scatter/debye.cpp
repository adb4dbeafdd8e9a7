// Debye-series decomposition of the Mie coefficients (equations and derivation: docs/debye.md).
//
// References:
//   [HL92] E. A. Hovenac and J. A. Lock, "Assessing the contributions of surface waves and complex
//          rays to far-field Mie scattering by use of the Debye series", J. Opt. Soc. Am. A 9,
//          781-795 (1992): the series a_n = 1/2 [1 - R22 - sum_p T21 R11^(p-1) T12] and the
//          partial-wave Fresnel coefficients (written there for exp(+i omega t)). The equations
//          here were derived anew in the B&H convention (docs/debye.md, Equations (D1)-(D11));
//          the tests against mie_coefficients and mpmath decide their signs.
//   [vdH]  H. C. van de Hulst, "Light Scattering by Small Particles" (Wiley 1957, Dover 1981),
//          chapters 12-13 (geometric optics and the rainbow orders p).
//   [BH]   C. F. Bohren and D. R. Huffman (1983), section 4.8: psi, chi, xi, D_n and eq. 4.89.
//   [Y03]  W. Yang, "Improved recursive algorithm for light scattering by a multilayered sphere",
//          Appl. Opt. 42, 1710-1720 (2003): the product psi_n xi_n recurred instead of xi_n
//          (used here, with xi2 in place of xi, for Im z > 2).
//
// Numerical scheme (notation of debye.hpp; G_n = xi_{n-1}/xi_n, so D_n = G_n - n/z):
// - xi1(z) (outgoing) grows with n for every Im z >= 0, so G1 is recurred upward:
//   G1_n = 1 / ((2n-1)/z - G1_{n-1}), G1_0 = i ([BH] recurrence for xi; Equation (D9)).
// - xi2(z) (incoming) shrinks with n while n < |z| when Im z > 0, by about exp(-Im z) overall:
//   the same upward recurrence amplifies rounding by up to ~exp(2 Im z). It is used as is for
//   Im z <= 2 (at most ~55 ulp). For Im z > 2, as in [Y03], Q_n = 1/(psi_n xi2_n) is recurred and
//   G2_n = psi_{n-1}/psi_n - i Q_n (Wronskian psi xi2' - psi' xi2 = -i; Equation (D10)); an error
//   in Q then moves G2 by |Q| ~ exp(-2 Im z) times it, so nothing grows. Once |Q| > |psi_{n-1}/
//   psi_n| / 2 (n past the turning point, where the subtraction would cancel and xi2 grows again
//   with n) the plain upward recurrence takes over, stable from there.
// - xi1/xi2, 1/xi^2, psi/xi2 and 1/(psi xi2) are products over n, kept as a mantissa and a
//   separate power of two, so that exp(2 i z) with Im z up to 1e5 neither underflows too early
//   nor overflows (Equation (D11) gives their values at n = 0).
// - The recurrences run in long double (see below), D_n(z) starting past |z| where the shared
//   double start's error is damped; the differences D1(x) - kappa D2(z) etc. are formed in long
//   double (they cancel by ~700 near the edge); the rest of the per-n formulas in double.
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/core/complex.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "hydrolux/core/error.hpp"
#include "hydrolux/scatter/riccati_bessel.hpp"

namespace hydrolux::scatter {

namespace {

// The recurrences run in long double (64-bit significand on x86-64): the products over n that
// give xi1/xi2 and 1/xi^2 accumulate rounding coherently, ~N ulp, which in double would be 1e-12
// at x = 1e4 and 1e-11 at x = 1e5 (measured against mpmath); in long double it is ~1e-15. Complex
// arithmetic is written out (struct CL) because std::complex<long double> multiplication and
// division go through the NaN-checking library calls __mulxc3/__divxc3, ten times slower; the
// magnitudes here stay far inside the long double range, so the textbook formulas are safe.
using Real = long double;

struct CL {
  Real re = 0, im = 0;
  constexpr CL() = default;
  constexpr CL(Real r, Real i = 0) : re(r), im(i) {}
  explicit CL(Complex c) : re(c.real()), im(c.imag()) {}
  explicit operator Complex() const { return {static_cast<double>(re), static_cast<double>(im)}; }
};
inline CL operator+(CL a, CL b) { return {a.re + b.re, a.im + b.im}; }
inline CL operator-(CL a, CL b) { return {a.re - b.re, a.im - b.im}; }
inline CL operator-(CL a) { return {-a.re, -a.im}; }
inline CL operator*(CL a, CL b) { return {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
inline CL operator*(Real s, CL a) { return {s * a.re, s * a.im}; }
inline CL inverse(CL a) {
  const Real r = 1 / (a.re * a.re + a.im * a.im);
  return {a.re * r, -a.im * r};
}
inline CL operator/(CL a, CL b) { return a * inverse(b); }
inline CL conj(CL a) { return {a.re, -a.im}; }
inline Real abs1(CL a) { return std::fabs(a.re) + std::fabs(a.im); }  // |a| within a factor 1.42

constexpr CL kI{0.0L, 1.0L};

// Stand-ins for an exact zero in a denominator (as the modified Lentz method does): finite
// results where a ratio has a pole. nonzero(v, a, b, c) for v = a - b - c: the rounding level of
// the terms whose difference vanished, in double.
CL nonzero(CL v) { return v.re == 0 && v.im == 0 ? CL(1e-300L) : v; }
Complex nonzero(CL v, CL a, CL b, CL c) {
  if (v.re != 0 || v.im != 0) return Complex(v);
  return static_cast<double>(abs1(a) + abs1(b) + abs1(c)) * std::numeric_limits<double>::epsilon();
}


// Above this Im z, xi2 is built from Q = 1/(psi xi2) ([Y03]); below, by the direct recurrence.
constexpr double kDirectMaxImag = 2.0;

// v * 2^e: a complex number whose magnitude may lie far outside the floating-point range
// (exp(-2 Im z) reaches e^-200000).
struct Scaled {
  CL v{1.0L};
  long e = 0;

  void normalise() {
    constexpr Real kHi = 0x1p256L, kLo = 0x1p-256L;
    const Real a = std::max(std::fabs(v.re), std::fabs(v.im));
    if ((a > kHi || a < kLo) && a != 0 && std::isfinite(a)) {  // rarely: keep it off the fast path
      const int k = std::ilogb(a);
      v = CL(std::scalbn(v.re, -k), std::scalbn(v.im, -k));
      e += k;
    }
  }
  Scaled& operator*=(CL c) {
    v = v * c;
    normalise();
    return *this;
  }
  Scaled& operator*=(const Scaled& s) {
    v = v * s.v;
    e += s.e;
    normalise();
    return *this;
  }
  // The value in double: flushed to 0 below the double range, never infinite (the clamp is never
  // reached for the quantities formed here, which are bounded amplitudes).
  Complex value() const { return Complex(v) * pow2(e); }

  // 2^k as a double, built from its bits (exact; 0 below 2^-1074); libm's scalbn on long double
  // was a fifth of the run time.
  static double pow2(long k) {
    if (k == 0) return 1.0;
    if (k < -1074) return 0.0;
    if (k > 1023) k = 1023;
    if (k < -1022) return std::bit_cast<double>(std::uint64_t{1} << (k + 1074));  // subnormal
    return std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
  }
};

// factor * exp(2 i z) for Im z >= 0, or factor * exp(-2 i z) when `negative`.
Scaled scaled_exp_2iz(Complex z, bool negative, CL factor = 1.0L) {
  const Real re = z.real(), im = z.imag();
  const Real phase = negative ? -2 * re : 2 * re;
  const Real log_mag = negative ? 2 * im : -2 * im;
  Scaled s;
  // The magnitude as 2^e * 2^frac with e an integer, so that e^(+-200000) is no problem.
  const Real log2_mag = log_mag / std::log(2.0L);
  s.e = static_cast<long>(std::floor(log2_mag));
  const Real mag = std::exp2(log2_mag - static_cast<Real>(s.e));
  s.v = factor * CL(mag * std::cos(phase), mag * std::sin(phase));
  s.normalise();
  return s;
}

// Upward recurrence of the Riccati-Bessel/Hankel ratios of one argument z (Im z >= 0), order by
// order. After step(n):
//   g1 = xi1_{n-1}/xi1_n,  g2 = xi2_{n-1}/xi2_n,  gpsi = psi_{n-1}/psi_n,
//   rho = xi1_n/xi2_n,  inv1_sq = 1/xi1_n^2,  inv2_sq = 1/xi2_n^2,
//   psi_xi2 = psi_n/xi2_n,  q = 1/(psi_n xi2_n).
// Order 0 (Equation (D11)): psi_0 = sin z, xi1_0 = -i e^{iz}, xi2_0 = i e^{-iz}.
class HankelRatios {
 public:
  // z is taken as the double the Mie solver uses (m * x rounded once), so that both solve the
  // same problem; the arithmetic from there on is in long double.
  // `outside`: x real, outside the sphere (rho, 1/xi1^2, psi/xi2 needed); otherwise z = m x inside
  // (rho, 1/xi2^2, 1/(psi xi2) needed).
  HankelRatios(Complex z, int n_max, bool outside) : zinv_(inverse(CL(z))), outside_(outside) {
    g1 = kI;
    g2 = -kI;
    rho = scaled_exp_2iz(z, false, -1.0L);     // -e^{2iz}
    inv2_sq = rho;                             // 1/(i e^{-iz})^2 = -e^{2iz}
    inv1_sq = scaled_exp_2iz(z, true, -1.0L);  // 1/(-i e^{iz})^2 = -e^{-2iz}
    // psi_0/xi2_0 = (1 - e^{2iz})/2 and 1/(psi_0 xi2_0) = -2 e^{2iz} / (1 - e^{2iz}).
    const CL e2(scaled_exp_2iz(z, false).value());
    psi_xi2.v = 0.5L * (CL(1.0L) - e2);
    psi_xi2.normalise();
    q = scaled_exp_2iz(z, false, -2.0L * inverse(CL(1.0L) - e2));
    // D_n(z) = psi_n'/psi_n by [BH] eq. 4.89 downward in long double, from the shared solver's
    // exact (Lentz continued fraction) value in double. The recurrence damps an error in its
    // start only where n > |z| (for real z; everywhere when Im z > 0), so it starts at least
    // 8 |z|^(1/3) + 16 orders past |z|, where the start's 1e-16 has decayed below 1e-19; started at
    // n_max ~ x + 4 x^(1/3), D(m x) kept ~1e-16 and T21 T12 / (1 - R11) lost up to 6e-12 to it
    // through the cancelling Mie denominator.
    const double z_abs = std::abs(z);
    const int n_start =
        std::max(n_max, static_cast<int>(std::min(z_abs + 8 * std::cbrt(z_abs) + 16, 2e7)));
    CL d = CL(log_derivative_psi(z, n_start)[static_cast<std::size_t>(n_start)]);
    dpsi_.resize(static_cast<std::size_t>(n_max) + 1);
    for (int n = n_start; n >= 1; --n) {
      if (n <= n_max) dpsi_[static_cast<std::size_t>(n)] = d;
      const CL n_over_z = static_cast<Real>(n) * zinv_;
      d = n_over_z - inverse(nonzero(d + n_over_z));  // Equation (4.89) [BH]
    }
    dpsi_[0] = d;
    direct_ = z.imag() <= kDirectMaxImag;
  }

  void step(int n) {
    const CL c = static_cast<Real>(2 * n - 1) * zinv_;
    gpsi = dpsi_[static_cast<std::size_t>(n)] + static_cast<Real>(n) * zinv_;
    g1 = inverse(nonzero(c - g1));  // Equation (D9)
    if (outside_) {
      // Real x: xi2 = conj(xi1), so G2 = conj(G1) and rho = xi1/xi2 has modulus 1.
      g2 = conj(g1);
      rho *= g2 / g1;
      inv1_sq *= g1 * g1;
      psi_xi2 *= g2 / gpsi;
      return;
    }
    const CL g2_direct = inverse(nonzero(c - g2));  // Equation (D9) for xi2
    q *= gpsi * g2_direct;  // Q_n = Q_{n-1} (psi_{n-1}/psi_n) (xi2_{n-1}/xi2_n)
    if (direct_) {
      g2 = g2_direct;
    } else {
      const CL qv = q.v * static_cast<Real>(Scaled::pow2(q.e));
      g2 = gpsi - kI * qv;  // Equation (D10)
      if (abs1(qv) > 0.5L * abs1(gpsi)) direct_ = true;
    }
    rho *= g2 / g1;
    inv2_sq *= g2 * g2;
  }

  CL g1, g2, gpsi;
  Scaled rho, inv1_sq, inv2_sq, psi_xi2, q;

 private:
  CL zinv_;
  bool outside_;
  bool direct_ = true;
  std::vector<CL> dpsi_;
};

void validate(Complex m, double x, int n_terms) {
  require_in_range("x", x, kMinSizeParameter, kMaxSizeParameter, "Debye series");
  require_in_range("m_real", m.real(), kMinIndexReal, kMaxIndexReal, "Debye series");
  require_in_range("m_imag", m.imag(), 0.0, kMaxIndexImag, "Debye series");
  require_in_range("n_terms", n_terms, 0, 1e6, "Debye series (0 = mie_terms(x))");
}

void validate_order(int p) { require_in_range("p", p, 0, kMaxDebyeOrder, "Debye series order"); }

// r^k for k >= 0 by squaring (std::pow(complex, int) goes through exp/log).
Complex power(Complex r, int k) {
  Complex result = 1.0;
  while (k > 0) {
    if (k & 1) result *= r;
    k >>= 1;
    if (k) r *= r;
  }
  return result;
}

// coef r^k (k >= 0). Where |R11| > 1 (an absorbing m: slightly, 1.065 for 1.333 + i at x = 3;
// far, for m = 0.001 + i or next to a pole of the Debye terms) the orders grow geometrically and
// the series diverges for that partial wave; a term beyond ~1e304 saturates there, with its
// phase, rather than overflowing to inf (and to NaN in a later sum).
Complex times_power(Complex coef, Complex r, int k) {
  if (k == 0 || coef == Complex(0)) return coef;
  const double k_log_r = k * std::log(std::abs(r));
  if (k_log_r < 600) return coef * power(r, k);  // |r^k| < e^600 (r = 0 gives -inf)
  const double log_mag = std::log(std::abs(coef)) + k_log_r;
  return std::polar(std::exp(std::min(log_mag, 700.0)), std::arg(coef) + k * std::arg(r));
}

MieCoefficients empty_like(const DebyeInterface& d) {
  MieCoefficients c;
  c.m = d.m;
  c.x = d.x;
  c.a.resize(static_cast<std::size_t>(d.terms()));
  c.b.resize(static_cast<std::size_t>(d.terms()));
  return c;
}

// Sum over orders p_first..p_last of one coefficient (Equations (D6), (D7)).
Complex orders_one(Complex one_minus_r22, Complex r11, Complex t, int p_first, int p_last) {
  Complex sum = p_first == 0 ? 0.5 * one_minus_r22 : Complex(0);
  const int first = std::max(p_first, 1);
  if (p_last < first) return sum;
  if (std::abs(r11) <= 1) {
    // sum_{p=first}^{last} R11^(p-1): every power is at most 1 in size.
    Complex rp = power(r11, first - 1);
    Complex geometric = 0;
    for (int p = first; p <= p_last && rp != Complex(0); ++p) {
      geometric += rp;
      rp *= r11;
    }
    return sum - 0.5 * t * geometric;
  }
  // |R11| > 1: factor out the largest power, R11^(last-1) sum_{j=0}^{last-first} R11^(-j).
  const Complex q = 1.0 / r11;
  Complex qj = 1.0, tail = 0;
  for (int j = 0; j <= p_last - first; ++j) {
    tail += qj;
    qj *= q;
  }
  return sum + times_power(-0.5 * t * tail, r11, p_last - 1);
}

}  // namespace

DebyeInterface debye_interface(Complex m, double x, int n_terms) {
  validate(m, x, n_terms);
  const int n_max = n_terms > 0 ? n_terms : mie_terms(x);
  DebyeInterface d;
  d.m = m;
  d.x = x;
  for (DebyeFresnel* f : {&d.a, &d.b})
    for (auto* v : {&f->r22, &f->r11, &f->t21t12, &f->one_minus_r22, &f->transmitted})
      v->resize(static_cast<std::size_t>(n_max));
  HankelRatios out(Complex(x, 0.0), n_max, true), in(m * x, n_max, false);
  // The recurrences need long double; the formulas for each n below do not (no accumulation),
  // so they run in double.
  const CL kappa_a = inverse(CL(m)), kappa_b = CL(m);
  // D_n = G_n - n/z. In D1(x) - kappa D2(z) = G1(x) - kappa G2(z) - (n/x)(1 - kappa/m) the n/z
  // parts are collected, so that they cancel exactly for b_n (kappa/m = 1) rather than in
  // rounding (they dominate once n > x).
  const CL shift_a = CL(1.0L) - inverse(CL(m) * CL(m));
  for (int n = 1; n <= n_max; ++n) {
    out.step(n);
    in.step(n);
    const auto i = static_cast<std::size_t>(n - 1);
    // Real x: xi2(x) = conj(xi1(x)), so psi/xi1 = conj(psi/xi2) and 1/rho = conj(rho).
    const Complex rx = std::conj(out.rho.value());            // xi2(x)/xi1(x)
    const Complex psi_xi1x = std::conj(out.psi_xi2.value());  // psi(x)/xi1(x)
    const Complex rho_z = in.rho.value();                     // xi1(z)/xi2(z)
    Scaled t = out.inv1_sq;                                   // 1 / (xi1(x)^2 xi2(z)^2)
    t *= in.inv2_sq;
    Scaled all = out.inv1_sq;  // 1 / (xi1(x)^2 psi(z) xi2(z))
    all *= in.q;
    const Complex t_v(t.v), all_v(all.v);
    const double t_scale = Scaled::pow2(t.e), all_scale = Scaled::pow2(all.e);
    for (int mode = 0; mode < 2; ++mode) {
      const CL kappa = mode == 0 ? kappa_a : kappa_b;
      const CL shift = mode == 0 ? (static_cast<Real>(n) / x) * shift_a : CL(0.0L);
      DebyeFresnel& f = mode == 0 ? d.a : d.b;
      // The differences of G's in long double (they cancel by up to ~1e3 near the edge, which
      // in double cost 6e-12 of D1(x) - kappa D(z)); the rest in double.
      const CL kg2z = kappa * in.g2;
      const CL den = out.g1 - kg2z - shift;                 // D1(x) - kappa D2(z)
      const CL mie_den = out.g1 - kappa * in.gpsi - shift;  // D1(x) - kappa D(z)
      const Complex num22(conj(out.g1) - kg2z - shift);     // D2(x) - kappa D2(z)
      const Complex num22c(out.gpsi - kg2z - shift);        // D(x) - kappa D2(z)
      const Complex num11(kappa * in.g1 - out.g1 + shift);  // kappa D1(z) - D1(x)
      // den vanishes where R22, R11 and T21 T12 have a pole (possible only for absorbing m:
      // e.g. m = 0.5 + 0.5i, x = 1, n = 1, b_n); there the orders are infinite and only their sum
      // is finite. An exact zero is replaced by its rounding level, so that the result stays
      // finite (docs/debye.md, "Poles"). mie_den never vanishes for real x (no bound states).
      const Complex inv_den = reciprocal(nonzero(den, out.g1, kg2z, shift));
      const Complex inv_mie_den = reciprocal(nonzero(mie_den, out.g1, kappa * in.gpsi, shift));
      const Complex kap(kappa);
      f.r22[i] = -rx * num22 * inv_den;                                  // Equation (D3)
      f.one_minus_r22[i] = 2.0 * psi_xi1x * num22c * inv_den;            // Equation (D3')
      f.r11[i] = rho_z * num11 * inv_den;                                // Equation (D4)
      f.t21t12[i] = (t_v * (-4.0 * kap * inv_den * inv_den)) * t_scale;  // Equation (D5)
      f.transmitted[i] = (all_v * (-2.0 * kap * inv_den * inv_mie_den)) * all_scale;  // (D5')
    }
  }
  return d;
}

MieCoefficients debye_orders(const DebyeInterface& d, int p_first, int p_last) {
  validate_order(p_first);
  validate_order(p_last);
  if (p_last < p_first)
    throw DomainError("p", p_last, p_first, kMaxDebyeOrder, "Debye series: p_last >= p_first");
  MieCoefficients c = empty_like(d);
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    c.a[i] = orders_one(d.a.one_minus_r22[i], d.a.r11[i], d.a.t21t12[i], p_first, p_last);
    c.b[i] = orders_one(d.b.one_minus_r22[i], d.b.r11[i], d.b.t21t12[i], p_first, p_last);
  }
  return c;
}

MieCoefficients debye_coefficients(const DebyeInterface& d, int p) { return debye_orders(d, p, p); }

MieCoefficients debye_coefficients(Complex m, double x, int p, int n_terms) {
  validate_order(p);
  return debye_orders(debye_interface(m, x, n_terms), p, p);
}

MieCoefficients debye_sum(Complex m, double x, int p_max, int n_terms) {
  validate_order(p_max);
  return debye_orders(debye_interface(m, x, n_terms), 0, p_max);
}

MieCoefficients debye_remainder(const DebyeInterface& d, int p_max) {
  validate_order(p_max);
  MieCoefficients c = empty_like(d);
  const auto rest = [p_max](Complex r11, Complex transmitted) {  // Equation (D8)
    return times_power(-0.5 * transmitted, r11, p_max);
  };
  for (std::size_t i = 0; i < c.a.size(); ++i) {
    c.a[i] = rest(d.a.r11[i], d.a.transmitted[i]);
    c.b[i] = rest(d.b.r11[i], d.b.transmitted[i]);
  }
  return c;
}

MieCoefficients debye_remainder(Complex m, double x, int p_max, int n_terms) {
  validate_order(p_max);
  return debye_remainder(debye_interface(m, x, n_terms), p_max);
}

MieCoefficients debye_closed_form(const DebyeInterface& d) {
  MieCoefficients c = empty_like(d);
  for (std::size_t i = 0; i < c.a.size(); ++i) {  // Equation (D2)
    c.a[i] = 0.5 * (d.a.one_minus_r22[i] - d.a.transmitted[i]);
    c.b[i] = 0.5 * (d.b.one_minus_r22[i] - d.b.transmitted[i]);
  }
  return c;
}

}  // namespace hydrolux::scatter
