#pragma once
// Fresnel equations for a plane interface: dielectric (both sides, total internal reflection
// included) and absorbing media (conductors) with a complex index. Exact; no Schlick.
//
// Conventions of the complex index and of the interface (bsdf.hpp and the scattering code use the same):
// - Complex index n = eta + i k with k >= 0 absorbing (time dependence exp(-i omega t), as in
//   Bohren & Huffman).
// - Light arrives in a transparent medium of real index n_i at angle theta_i (cos_i in [0, 1])
//   onto a medium of index n_t. The transmitted wave's normal wavenumber is
//   w = n_t cos(theta_t) = sqrt(n_t^2 - n_i^2 sin^2 theta_i), principal branch (Re, Im >= 0): a
//   wave that decays away from the interface, evanescent under total internal reflection.
// - Amplitude ratios of the electric field follow Hecht, Optics (5th ed.), eqs. 4.34, 4.35,
//   4.40, 4.41:
//     r_s = (n_i cos_i - n_t cos_t) / (n_i cos_i + n_t cos_t)
//     r_p = (n_t cos_i - n_i cos_t) / (n_t cos_i + n_i cos_t)
//     t_s = 2 n_i cos_i / (n_i cos_i + n_t cos_t)
//     t_p = 2 n_i cos_i / (n_t cos_i + n_i cos_t)
//   so r_p = -r_s at normal incidence. Power reflectances R = |r|^2; power transmittances
//   T = (n_t cos_t) / (n_i cos_i) |t|^2 (the ratio of the normal energy fluxes), so R + T = 1.
// - Unpolarised light: R = (R_s + R_p) / 2, T = (T_s + T_p) / 2.
#include <complex>

#include "hydrolux/core/math.hpp"

namespace hydrolux::optics {

template <typename Float>
struct FresnelAmplitudes {
  std::complex<Float> r_s, r_p, t_s, t_p;
  std::complex<Float> nt_cos_t;  // n_t cos(theta_t), the branch described above
};

// Amplitude coefficients for any n_t (real, complex, above or below n_i).
template <typename Float>
FresnelAmplitudes<Float> fresnel_amplitudes(Float cos_i, Float n_i, std::complex<Float> n_t) noexcept {
  using C = std::complex<Float>;
  const Float sin2_i = std::max(Float(0), Float(1) - cos_i * cos_i);
  const C w = std::sqrt(n_t * n_t - C(n_i * n_i * sin2_i));  // principal branch: Re, Im >= 0
  const C ni_cos_i(n_i * cos_i);
  const C nt2_cos_i = n_t * n_t * cos_i;
  const C ni_w = n_i * w;
  // n_t cos_t = w, so r_p and t_p are multiplied through by n_t to avoid dividing by it.
  FresnelAmplitudes<Float> a;
  a.nt_cos_t = w;
  const C ds = ni_cos_i + w;
  const C dp = nt2_cos_i + ni_w;
  if (ds == C(0) || dp == C(0)) {  // grazing incidence on an index-matched medium: no interface
    a.r_s = a.r_p = C(0);
    a.t_s = a.t_p = C(1);
    return a;
  }
  a.r_s = (ni_cos_i - w) / ds;
  a.r_p = (nt2_cos_i - ni_w) / dp;
  a.t_s = Float(2) * ni_cos_i / ds;
  a.t_p = Float(2) * ni_cos_i * n_t / dp;
  return a;
}

template <typename Float>
struct FresnelDielectric {
  std::complex<Float> r_s, r_p, t_s, t_p;  // amplitude ratios (complex under TIR)
  Float R_s, R_p, R;                       // power reflectances
  Float T_s, T_p, T;                       // power transmittances, 0 under TIR
  Float cos_t;                             // cos(theta_t); 0 under TIR
  bool tir;                                // total internal reflection
};

// Dielectric interface, real indices n_i, n_t > 0, cos_i in [0, 1].
template <typename Float>
FresnelDielectric<Float> fresnel_dielectric(Float cos_i, Float n_i, Float n_t) noexcept {
  const auto a = fresnel_amplitudes(cos_i, n_i, std::complex<Float>(n_t));
  FresnelDielectric<Float> f;
  f.r_s = a.r_s;
  f.r_p = a.r_p;
  f.t_s = a.t_s;
  f.t_p = a.t_p;
  const Float sin2_i = std::max(Float(0), Float(1) - cos_i * cos_i);
  f.tir = n_i * n_i * sin2_i > n_t * n_t;  // at exactly the critical angle R = 1 all the same
  if (f.tir || cos_i <= 0) {  // all power reflected (at grazing incidence the flux is zero anyway)
    f.R_s = f.R_p = f.R = Float(1);
    f.T_s = f.T_p = f.T = Float(0);
    f.cos_t = Float(0);
    if (!f.tir) f.cos_t = safe_sqrt(Float(1) - sqr(n_i / n_t) * sin2_i);
    return f;
  }
  f.R_s = std::norm(a.r_s);
  f.R_p = std::norm(a.r_p);
  f.R = (f.R_s + f.R_p) / 2;
  const Float nt_cos_t = a.nt_cos_t.real();
  const Float flux_ratio = nt_cos_t / (n_i * cos_i);
  f.T_s = flux_ratio * std::norm(a.t_s);
  f.T_p = flux_ratio * std::norm(a.t_p);
  f.T = (f.T_s + f.T_p) / 2;
  f.cos_t = nt_cos_t / n_t;
  return f;
}

template <typename Float>
struct FresnelConductor {
  std::complex<Float> r_s, r_p;  // amplitude ratios
  Float R_s, R_p, R;             // power reflectances; 1 - R is absorbed
};

// Absorbing medium of complex index n_t = eta + i k seen from a transparent medium n_i; exact.
template <typename Float>
FresnelConductor<Float> fresnel_conductor(Float cos_i, Float n_i, std::complex<Float> n_t) noexcept {
  const auto a = fresnel_amplitudes(cos_i, n_i, n_t);
  FresnelConductor<Float> f;
  f.r_s = a.r_s;
  f.r_p = a.r_p;
  f.R_s = std::norm(a.r_s);
  f.R_p = std::norm(a.r_p);
  f.R = (f.R_s + f.R_p) / 2;
  return f;
}

// Unpolarised dielectric reflectance for the BSDFs, real arithmetic. eta = n_below / n_above;
// cos_i = cos(theta_i) measured from the "above" normal: negative means the light arrives from
// below, and the indices swap. Returns 1 under total internal reflection.
template <typename Float>
Float fr_dielectric(Float cos_i, Float eta) noexcept {
  cos_i = std::clamp(cos_i, Float(-1), Float(1));
  if (cos_i < 0) {
    eta = Float(1) / eta;
    cos_i = -cos_i;
  }
  const Float sin2_t = (Float(1) - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= Float(1)) return Float(1);
  const Float cos_t = safe_sqrt(Float(1) - sin2_t);
  const Float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const Float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return (r_s * r_s + r_p * r_p) / 2;
}

// Unpolarised reflectance of an absorbing medium with relative complex index eta (n_t / n_i),
// cos_i in [0, 1].
template <typename Float>
Float fr_conductor(Float cos_i, std::complex<Float> eta) noexcept {
  return fresnel_conductor(std::clamp(cos_i, Float(0), Float(1)), Float(1), eta).R;
}

}  // namespace hydrolux::optics
