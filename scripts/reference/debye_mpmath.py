#!/usr/bin/env python3
"""High-precision reference values for the Debye-series coefficients.

Used by tests/scatter/test_debye.cpp.

Prints one C++ initializer per case: m, x, n and, for a_n (kappa = 1/m) then b_n (kappa = m),
    R22, R11, T21 T12, 1 - R22, T21 T12 / (1 - R11), and the Mie coefficient,
each as {re, im}, to 17 significant digits.

Method (independent of the C++ code, which uses ratios and logarithmic derivatives in long
double): the Riccati-Hankel functions xi1_n(z) = z h_n^(1)(z) = psi_n - i chi_n and
xi2_n(z) = psi_n + i chi_n (Bohren & Huffman 1983, section 4.8) themselves, by the recurrence
    xi_{n+1} = (2n+1)/z xi_n - xi_{n-1},  xi1_{-1} = e^{iz}, xi1_0 = -i e^{iz},
                                          xi2_{-1} = e^{-iz}, xi2_0 = i e^{-iz},
in mpmath at a working precision chosen so that the recurrence's worst amplification
(~e^{2 Im z} for xi2 while n < |z|, and psi = (xi1 + xi2)/2 cancelling ~chi/psi past n ~ x) still
leaves more than 30 digits; every case is run again at 40 more digits and must agree to 1e-25.
Then, with D = xi'/xi, xi_n' = xi_{n-1} - (n/z) xi_n:
    R22 = -(xi2(x)/xi1(x)) (D2(x) - kappa D2(z)) / (D1(x) - kappa D2(z))
    R11 = -(xi1(z)/xi2(z)) (kappa D1(z) - D1(x)) / (kappa D2(z) - D1(x))
    T21 T12 = -4 kappa / (xi1(x)^2 xi2(z)^2 (D1(x) - kappa D2(z))^2)
(docs/debye.md, Equations (D3)-(D5)), and the Mie coefficients from Bohren & Huffman eq. 4.88.

z = m x is the double-precision product, as the library forms it (x and m are doubles; the
exact decimal m x would differ from the library's problem by 1e-16 relative, which moves the
phases of R11 and T21 T12 by ~|z| 1e-16).

Usage: python3 scripts/reference/debye_mpmath.py   (mpmath 1.3.0; ~1 minute)
"""
import mpmath as mp

# (m, x, n): the Debye test's reference cases. Chosen to cover the numerical regimes of
# src/scatter/debye.cpp: small x; n < x (rays hit the sphere); n just past x (edge, tunnelling;
# at x = 1e4, n = 10055 the Mie denominator D1(x) - m D(m x) cancels by ~700);
# a non-absorbing water drop at x = 1e4; Im(m x) = 10 and 50 (the Q = 1/(psi xi2) path, Im z > 2);
# Im(m x) = 500 (R11 and T21 T12 ~ e^-1000: zero in double); m < 1 (a bubble); n > |m x| with
# Im(m x) = 50 (the Q path hands over to the direct recurrence); x = 1e5.
CASES = [
    (1.333 + 0j, 0.1, 1),
    (1.5 + 0j, 1.0, 2),
    (1.333 + 0j, 10.0, 5),
    (1.333 + 0j, 100.0, 50),
    (1.333 + 0j, 100.0, 105),
    (1.333 + 1e-3j, 1000.0, 700),
    (1.333 + 0j, 1e4, 5000),
    (1.333 + 0j, 1e4, 10050),
    (1.333 + 0j, 1e4, 10055),
    (1.333 + 1e-3j, 1e4, 9000),
    (2 + 0.5j, 100.0, 60),
    (1.333 + 0.1j, 5000.0, 3000),
    (0.75 + 0j, 100.0, 90),
    (0.5 + 0.5j, 100.0, 110),
    (1.333 + 0j, 1e5, 70000),
]


def xi_pair(z, nmax):
    """xi1_n(z), xi2_n(z) for n = 0..nmax (lists), at the current mpmath precision."""
    x1 = [mp.mpc(0)] * (nmax + 1)
    x2 = [mp.mpc(0)] * (nmax + 1)
    e = mp.exp(1j * z)
    em = 1 / e
    x1[0], x2[0] = -1j * e, 1j * em
    p1, p2 = e, em  # order -1
    for n in range(0, nmax):
        n1 = (2 * n + 1) / z * x1[n] - p1
        n2 = (2 * n + 1) / z * x2[n] - p2
        p1, p2 = x1[n], x2[n]
        x1[n + 1], x2[n + 1] = n1, n2
    return x1, x2


def coefficients(m, x, n, extra):
    """The Debye and Mie quantities of partial wave n, for kappa = 1/m (a) and kappa = m (b)."""
    z_double = complex(m) * x  # the library's z = m * x in double
    # Digits lost: e^{2 Im z} in the xi2 recurrence (2 Im z / ln 10), and chi/psi in
    # psi = (xi1 + xi2)/2 past n ~ x (far fewer than the generous 2.6 (n - x) allowed here); the
    # second run at 40 more digits checks the choice.
    loss = 2 * z_double.imag / 2.3 + 2.6 * max(n - x, 0) + 40
    with mp.workdps(int(60 + loss + extra)):
        xr = mp.mpf(x)
        zr = mp.mpc(z_double.real, z_double.imag)
        mr = mp.mpc(complex(m).real, complex(m).imag)
        X1, X2 = xi_pair(xr, n)
        Z1, Z2 = xi_pair(zr, n)

        def deriv(seq, w):
            return seq[n - 1] - n / w * seq[n]

        d1x, d2x = deriv(X1, xr) / X1[n], deriv(X2, xr) / X2[n]
        d1z, d2z = deriv(Z1, zr) / Z1[n], deriv(Z2, zr) / Z2[n]
        psix, psiz = (X1[n] + X2[n]) / 2, (Z1[n] + Z2[n]) / 2
        dpsix, dpsiz = (deriv(X1, xr) + deriv(X2, xr)) / 2, (deriv(Z1, zr) + deriv(Z2, zr)) / 2
        out = []
        for mode, kappa in (("a", 1 / mr), ("b", mr)):
            den = d1x - kappa * d2z
            r22 = -(X2[n] / X1[n]) * (d2x - kappa * d2z) / den
            r11 = -(Z1[n] / Z2[n]) * (kappa * d1z - d1x) / (kappa * d2z - d1x)
            t = -4 * kappa / (X1[n] ** 2 * Z2[n] ** 2 * den ** 2)
            dxi1x = deriv(X1, xr)
            if mode == "a":  # B&H eq. 4.88
                mie = (mr * psiz * dpsix - psix * dpsiz) / (mr * psiz * dxi1x - X1[n] * dpsiz)
            else:
                mie = (psiz * dpsix - mr * psix * dpsiz) / (psiz * dxi1x - mr * X1[n] * dpsiz)
            out.append([r22, r11, t, 1 - r22, t / (1 - r11), mie])
        return out


def fmt(v):
    def one(r):
        r = float(r) if abs(r) >= mp.mpf("1e-300") else 0.0
        return "%.17g" % r

    return "{%s, %s}" % (one(v.real), one(v.imag))


def main():
    print("// Generated by scripts/reference/debye_mpmath.py (mpmath %s)." % mp.__version__)
    for m, x, n in CASES:
        lo = coefficients(m, x, n, 0)
        hi = coefficients(m, x, n, 40)
        for row_lo, row_hi in zip(lo, hi):
            for a, b in zip(row_lo, row_hi):
                scale = max(abs(b), mp.mpf("1e-300"))
                assert abs(a - b) / scale < mp.mpf("1e-25"), (m, x, n)
        mm = complex(m)
        names = ["R22", "R11", "T21 T12", "1 - R22", "T21 T12 / (1 - R11)", "Mie"]
        lines = ["%s,  // %s: %s" % (fmt(v), mode, name)
                 for mode, row in zip("ab", hi) for name, v in zip(names, row)]
        lines[-1] = lines[-1].replace(",  //", "}},  //", 1)
        print("    {{%.17g, %.17g}, %.17g, %d,  // m, x, n" % (mm.real, mm.imag, x, n))
        print("     {" + "\n      ".join(lines))

if __name__ == "__main__":
    main()
