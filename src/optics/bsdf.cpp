// BSDFs of a plane interface; conventions and references in include/hydrolux/optics/bsdf.hpp.
#include "hydrolux/optics/bsdf.hpp"

#include <cmath>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/random.hpp"
#include "hydrolux/optics/snell.hpp"

namespace hydrolux::optics {

namespace {

constexpr double kMinEta = 1e-3;
constexpr double kMaxEta = 1e3;
const Vec3 kNormal{0.0, 0.0, 1.0};

// A value that may be handed out: finite and non-negative, else 0.
double finite_or_zero(double v) noexcept { return (v >= 0 && std::isfinite(v)) ? v : 0.0; }

// A sample that may be handed out: finite f >= 0, finite pdf > 0, finite unit-length wi.
std::optional<BSDFSample> checked(const BSDFSample& s) noexcept {
  if (!(s.pdf > 0) || !std::isfinite(s.pdf) || !(s.f >= 0) || !std::isfinite(s.f)) {
    return std::nullopt;
  }
  if (!std::isfinite(s.wi.x) || !std::isfinite(s.wi.y) || !std::isfinite(s.wi.z)) {
    return std::nullopt;
  }
  return s;
}

// (n_o / n_i)^2 = 1 / etap^2 in Radiance mode, 1 in Importance mode (see bsdf.hpp).
double radiance_scale(double etap, TransportMode mode) noexcept {
  return mode == TransportMode::Radiance ? 1.0 / (etap * etap) : 1.0;
}

double sign_of(double z) noexcept { return z < 0 ? -1.0 : 1.0; }

}  // namespace

// ------------------------------------------------------------------------------------------------
// Fresnel
// ------------------------------------------------------------------------------------------------

Fresnel Fresnel::dielectric(double eta) {
  require_in_range("eta", eta, kMinEta, kMaxEta, "dielectric Fresnel (n_inside / n_outside)");
  return Fresnel(Kind::Dielectric, {eta, 0.0});
}

Fresnel Fresnel::conductor(std::complex<double> eta) {
  require_in_range("eta_real", eta.real(), 0.0, kMaxEta, "conductor Fresnel");
  require_in_range("eta_imag", eta.imag(), 0.0, 1e6, "conductor Fresnel (k >= 0 absorbs)");
  require_in_range("eta_abs", std::abs(eta), kMinEta, 1e6, "conductor Fresnel");
  return Fresnel(Kind::Conductor, eta);
}

// ------------------------------------------------------------------------------------------------
// Specular (delta) lobes
// ------------------------------------------------------------------------------------------------

std::optional<BSDFSample> SpecularReflection::sample(const Vec3& wo, double, const glm::dvec2&,
                                                     TransportMode) const noexcept {
  if (wo.z == 0) return std::nullopt;
  const Vec3 wi(-wo.x, -wo.y, wo.z);  // reflect(wo, +z)
  const double F = fresnel_.reflectance(wo.z);
  return checked({F / std::abs(wi.z), wi, 1.0, true, false, 1.0});
}

SpecularTransmission::SpecularTransmission(double eta) : eta_(eta) {
  require_in_range("eta", eta, kMinEta, kMaxEta, "specular transmission (n_inside / n_outside)");
}

std::optional<BSDFSample> SpecularTransmission::sample(const Vec3& wo, double, const glm::dvec2&,
                                                       TransportMode mode) const noexcept {
  if (wo.z == 0) return std::nullopt;
  const auto r = refract(wo, kNormal, eta_);
  if (!r) return std::nullopt;  // total internal reflection
  const double T = 1.0 - fr_dielectric(wo.z, eta_);
  const double f = T / std::abs(r->wt.z) * radiance_scale(r->eta, mode);
  return checked({f, r->wt, 1.0, true, true, r->eta});
}

SmoothDielectric::SmoothDielectric(double eta) : eta_(eta) {
  require_in_range("eta", eta, kMinEta, kMaxEta, "smooth dielectric (n_inside / n_outside)");
}

std::optional<BSDFSample> SmoothDielectric::sample(const Vec3& wo, double uc, const glm::dvec2&,
                                                   TransportMode mode) const noexcept {
  if (wo.z == 0) return std::nullopt;
  const double R = fr_dielectric(wo.z, eta_);
  const double T = 1.0 - R;
  if (uc < R / (R + T)) {
    const Vec3 wi(-wo.x, -wo.y, wo.z);
    return checked({R / std::abs(wi.z), wi, R / (R + T), true, false, 1.0});
  }
  const auto r = refract(wo, kNormal, eta_);
  if (!r) return std::nullopt;  // T = 0 here, so only reached with uc >= 1
  const double f = T / std::abs(r->wt.z) * radiance_scale(r->eta, mode);
  return checked({f, r->wt, T / (R + T), true, true, r->eta});
}

// ------------------------------------------------------------------------------------------------
// Torrance-Sparrow
// ------------------------------------------------------------------------------------------------

double TorranceSparrow::f(const Vec3& wo, const Vec3& wi, TransportMode) const noexcept {
  if (!same_hemisphere(wo, wi)) return 0.0;
  const auto wm = reflection_half_vector(wo, wi);
  if (!wm) return 0.0;
  const double F = fresnel_.reflectance(glm::dot(wo, *wm));
  return finite_or_zero(microfacet_brdf(F, distrib_.D(*wm), distrib_.G(wo, wi), wo.z, wi.z));
}

double TorranceSparrow::pdf(const Vec3& wo, const Vec3& wi) const noexcept {
  if (!same_hemisphere(wo, wi)) return 0.0;
  const auto wm = reflection_half_vector(wo, wi);
  if (!wm) return 0.0;
  const double c = sign_of(wo.z) * glm::dot(wo, *wm);  // |wo.wm| for a valid pair
  if (!(c > 0)) return 0.0;
  // D_wo(wm) / (4 |wo.wm|): Walter eq. 14 applied to the visible-normal density.
  return finite_or_zero(distrib_.D_visible(wo, *wm) / (4.0 * c));
}

std::optional<BSDFSample> TorranceSparrow::sample(const Vec3& wo, double, const glm::dvec2& u,
                                                  TransportMode) const noexcept {
  if (wo.z == 0) return std::nullopt;
  const Vec3 wm = distrib_.sample_visible_normal(wo, u.x, u.y);
  const double wo_m = glm::dot(wo, wm);
  const double c = sign_of(wo.z) * wo_m;
  if (!(c > 0)) return std::nullopt;
  const Vec3 wi = glm::normalize(reflect(wo, wm));
  if (!same_hemisphere(wo, wi)) return std::nullopt;  // reflected below the surface
  const double pdf = distrib_.D_visible(wo, wm) / (4.0 * c);
  const double f =
      microfacet_brdf(fresnel_.reflectance(wo_m), distrib_.D(wm), distrib_.G(wo, wi), wo.z, wi.z);
  return checked({f, wi, pdf, false, false, 1.0});
}

// ------------------------------------------------------------------------------------------------
// Rough dielectric (Walter et al. 2007)
// ------------------------------------------------------------------------------------------------

RoughDielectric::RoughDielectric(const MicrofacetDistribution& distrib, double eta)
    : distrib_(distrib), eta_(eta) {
  require_in_range("eta", eta, kMinEta, kMaxEta, "rough dielectric (n_inside / n_outside)");
}

BxDFFlags RoughDielectric::flags() const noexcept {
  if (eta_ == 1.0) return BxDFFlags::Transmission | BxDFFlags::Specular;
  return BxDFFlags::Reflection | BxDFFlags::Transmission | BxDFFlags::Glossy;
}

namespace {

// The geometry shared by RoughDielectric::f and ::pdf: the half vector of the pair and its
// cosines, or nothing when the pair cannot scatter (grazing, back-facing microfacet).
struct DielectricPair {
  Vec3 wm;
  double wo_m, wi_m;  // wo.wm, wi.wm
  double etap;        // n_i / n_o; 1 for reflection
  bool reflection;
};

std::optional<DielectricPair> dielectric_pair(const Vec3& wo, const Vec3& wi, double eta) noexcept {
  if (wo.z == 0 || wi.z == 0) return std::nullopt;
  const bool reflection = wo.z * wi.z > 0;
  // Transmission: wo above means wi is inside, n_i / n_o = n_inside / n_outside = eta.
  const double etap = reflection ? 1.0 : (wo.z > 0 ? eta : 1.0 / eta);
  const auto wm = transmission_half_vector(wo, wi, etap);  // Walter eqs. 13 / 16
  if (!wm) return std::nullopt;
  const double wo_m = glm::dot(wo, *wm);
  const double wi_m = glm::dot(wi, *wm);
  // Each direction must see the microfacet from its own side of the macro surface.
  if (!(wo_m * wo.z > 0) || !(wi_m * wi.z > 0)) return std::nullopt;
  return DielectricPair{*wm, wo_m, wi_m, etap, reflection};
}

}  // namespace

double RoughDielectric::f(const Vec3& wo, const Vec3& wi, TransportMode mode) const noexcept {
  if (eta_ == 1.0) return 0.0;
  const auto p = dielectric_pair(wo, wi, eta_);
  if (!p) return 0.0;
  const double F = fr_dielectric(p->wo_m, eta_);
  const double D = distrib_.D(p->wm);
  const double G = distrib_.G(wo, wi);
  if (p->reflection) return finite_or_zero(microfacet_brdf(F, D, G, wo.z, wi.z));
  const double ft =
      microfacet_btdf_importance(1.0 - F, D, G, p->wi_m, p->wo_m, wi.z, wo.z, p->etap);
  return finite_or_zero(ft * radiance_scale(p->etap, mode));
}

double RoughDielectric::pdf(const Vec3& wo, const Vec3& wi) const noexcept {
  if (eta_ == 1.0) return 0.0;
  const auto p = dielectric_pair(wo, wi, eta_);
  if (!p) return 0.0;
  const double R = fr_dielectric(p->wo_m, eta_);
  const double T = 1.0 - R;
  const double dvis = distrib_.D_visible(wo, p->wm);
  if (p->reflection) return finite_or_zero(dvis / (4.0 * std::abs(p->wo_m)) * R);
  return finite_or_zero(dvis * transmission_jacobian(p->wi_m, p->wo_m, p->etap) * T);
}

std::optional<BSDFSample> RoughDielectric::sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                                  TransportMode mode) const noexcept {
  if (wo.z == 0) return std::nullopt;
  if (eta_ == 1.0) return checked({1.0 / std::abs(wo.z), -wo, 1.0, true, true, 1.0});
  const Vec3 wm = distrib_.sample_visible_normal(wo, u.x, u.y);
  const double wo_m = glm::dot(wo, wm);
  if (!(wo_m * wo.z > 0)) return std::nullopt;
  const double R = fr_dielectric(wo_m, eta_);
  const double T = 1.0 - R;
  const double dvis = distrib_.D_visible(wo, wm);
  const double D = distrib_.D(wm);
  if (uc < R) {  // reflection, probability R / (R + T) = R
    const Vec3 wi = glm::normalize(reflect(wo, wm));
    if (!same_hemisphere(wo, wi)) return std::nullopt;
    const double pdf = dvis / (4.0 * std::abs(wo_m)) * R;
    const double f = microfacet_brdf(R, D, distrib_.G(wo, wi), wo.z, wi.z);
    return checked({f, wi, pdf, false, false, 1.0});
  }
  const auto r = refract(wo, wm, eta_);  // etap = n_i / n_o comes back as r->eta
  if (!r) return std::nullopt;
  const Vec3 wi = glm::normalize(r->wt);
  const double wi_m = glm::dot(wi, wm);
  if (!(wi.z * wo.z < 0) || !(wi_m * wi.z > 0)) return std::nullopt;
  const double etap = r->eta;
  const double pdf = dvis * transmission_jacobian(wi_m, wo_m, etap) * T;
  const double f =
      microfacet_btdf_importance(T, D, distrib_.G(wo, wi), wi_m, wo_m, wi.z, wo.z, etap);
  return checked({f * radiance_scale(etap, mode), wi, pdf, false, true, etap});
}

DirectionalAlbedo directional_albedo(const BxDF& bxdf, const Vec3& w_light, int samples,
                                     std::uint64_t seed) {
  require_in_range("samples", samples, 1, std::numeric_limits<int>::max());
  Rng rng(seed);
  double sum[2] = {0, 0}, sum2[2] = {0, 0};
  for (int i = 0; i < samples; ++i) {
    const double uc = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const auto s = bxdf.sample(w_light, uc, {u1, u2}, TransportMode::Importance);
    if (!s || !(s->pdf > 0)) continue;
    const double w = s->f * std::abs(s->wi.z) / s->pdf;
    const int k = s->is_transmission ? 1 : 0;
    sum[k] += w;
    sum2[k] += w * w;
  }
  const double n = samples;
  const auto stderr_of = [n](double s1, double s2) {
    return n > 1 ? std::sqrt(std::max(0.0, s2 / n - (s1 / n) * (s1 / n)) / (n - 1)) : 0.0;
  };
  return {sum[0] / n, sum[1] / n, stderr_of(sum[0], sum2[0]), stderr_of(sum[1], sum2[1])};
}

}  // namespace hydrolux::optics
