#pragma once
// BSDFs of a plane interface: perfectly smooth (delta) reflection and transmission, and rough
// microfacet reflection (Torrance-Sparrow) and reflection + transmission (Walter et al. 2007).
//
// Conventions of every BxDF here (the index and Fresnel conventions are fresnel.hpp's):
// - pbrt-v4 style f(wo, wi) in the local shading frame (normal +z, core/vec.hpp): light ARRIVES
//   along wi and LEAVES along wo; both are unit vectors pointing away from the surface.
//   f has units 1/sr; the scattered radiance is L_o(wo) = int f(wo, wi) L_i(wi) |cos theta_i| dwi.
// - eta = n_inside / n_outside, "inside" being the z < 0 side (water below, air above: eta
// = 1.333).
// - Indices of the two sides of a path: n_i on wi's side, n_o on wo's side; etap = n_i / n_o is
//   the relative index along the path (1 for reflection). BSDFSample::eta reports it.
// - TransportMode::Radiance: transmitted values carry the factor (n_o / n_i)^2 = 1 / etap^2
//   (radiance is compressed into the denser medium, seed 003: L_o = (n_o/n_i)^2 (1 - F) L_i).
//   TransportMode::Importance (light/particle tracing, the adjoint): no such factor. Then
//   f_importance(wo, wi) = f_radiance(wi, wo) (Veach 1997, ch. 5), and the generalised reciprocity
//   of the radiance BTDF reads f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2 (seed 003; Walter et al. 2007
//   §5.3). Reflection does not depend on the mode.
// - Delta (specular) lobes: f() and pdf() return 0 (a delta has no density); sample() returns f as
//   the coefficient of the delta (F / |cos theta_i| ...) and pdf as the discrete probability of
//   choosing that lobe, with is_delta set, so f |cos theta_i| / pdf is the path weight as usual.
// - Fresnel and Snell come from fresnel.hpp (fr_dielectric, fr_conductor) and snell.hpp (reflect,
//   refract): nothing is re-derived here.
// - Robustness: for every unit wo, wi (grazing, exactly normal, on the "wrong" side) f and pdf are
//   finite and >= 0, and sample() returns either a finite sample with pdf > 0 or nothing.
//
// Single wavelength: f and pdf are doubles. Hot paths allocate nothing; the BxDFs are small values.
//
// References:
//   Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through Rough
//     Surfaces", EGSR: half vectors eqs. 13 and 16, their Jacobians eqs. 14 and 17, BRDF eq. 20,
//     BTDF eq. 21.
//   Torrance & Sparrow 1967, JOSA 57(9), and Cook & Torrance 1982: the microfacet BRDF.
//   Heitz 2014, JCGT 3(2): height-correlated Smith G (eq. 99); Heitz 2018, JCGT 7(4) and Heitz &
//     d'Eon 2014, EGSR: sampling by visible normals (microfacet.hpp).
//   pbrt-v4 (Pharr, Jakob, Humphreys), ch. 9: the interface shape (f, pdf, sample, flags, mode).
#include <complex>
#include <cstdint>
#include <glm/vec2.hpp>
#include <optional>

#include "hydrolux/core/vec.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/microfacet.hpp"

namespace hydrolux::optics {

enum class TransportMode { Radiance, Importance };

// What a BxDF can do (bit set).
enum class BxDFFlags : std::uint8_t {
  None = 0,
  Reflection = 1 << 0,
  Transmission = 1 << 1,
  Glossy = 1 << 2,    // a density (rough microfacet lobes)
  Specular = 1 << 3,  // delta lobes
};
constexpr BxDFFlags operator|(BxDFFlags a, BxDFFlags b) noexcept {
  return static_cast<BxDFFlags>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
constexpr BxDFFlags operator&(BxDFFlags a, BxDFFlags b) noexcept {
  return static_cast<BxDFFlags>(static_cast<std::uint8_t>(a) & static_cast<std::uint8_t>(b));
}
constexpr bool has_flag(BxDFFlags set, BxDFFlags flag) noexcept {
  return (set & flag) != BxDFFlags::None;
}

// One sampled direction.
struct BSDFSample {
  double f = 0;                  // f(wo, wi); for a delta lobe, the coefficient of the delta
  Vec3 wi{0, 0, 1};              // sampled incident direction, unit, away from the surface
  double pdf = 0;                // solid-angle density; for a delta lobe, the lobe's probability
  bool is_delta = false;         // sampled from a delta lobe
  bool is_transmission = false;  // wi on the other side of the surface from wo
  double eta = 1;                // etap = n(wi side) / n(wo side); 1 for reflection
};

// ------------------------------------------------------------------------------------------------
// Fresnel models
// ------------------------------------------------------------------------------------------------

// Reflectance of the interface for a microfacet (or the macro surface), one of:
//   dielectric:     real eta = n_inside / n_outside; light may arrive from either side, total
//                   internal reflection included (fr_dielectric, fresnel.hpp);
//   conductor:      complex eta = n_t / n_outside (k >= 0 absorbing), seen from either side alike
//                   (fr_conductor on |cos|);
//   perfect mirror: F = 1 everywhere (for furnace tests and idealised mirrors).
class Fresnel {
 public:
  enum class Kind { Dielectric, Conductor, PerfectMirror };

  // Throw DomainError for a dielectric eta outside [1e-3, 1e3], or a conductor eta with real part
  // outside [0, 1e3], k outside [0, 1e6] or |eta| < 1e-3.
  static Fresnel dielectric(double eta);
  static Fresnel conductor(std::complex<double> eta);
  static Fresnel perfect_mirror() noexcept { return Fresnel(Kind::PerfectMirror, {1.0, 0.0}); }

  Kind kind() const noexcept { return kind_; }
  // The real eta (dielectric) or the complex one (conductor); 1 for the perfect mirror.
  std::complex<double> eta() const noexcept { return eta_; }

  // Unpolarised reflectance for cos_i = cos of the angle between the incident direction and the
  // (micro)normal, signed: negative means the light comes from the inside (z < 0) side.
  double reflectance(double cos_i) const noexcept {
    switch (kind_) {
      case Kind::Dielectric:
        return fr_dielectric(cos_i, eta_.real());
      case Kind::Conductor:
        return fr_conductor(std::abs(cos_i), eta_);
      case Kind::PerfectMirror:
        return 1.0;
    }
    return 1.0;
  }

 private:
  Fresnel(Kind kind, std::complex<double> eta) noexcept : kind_(kind), eta_(eta) {}
  Kind kind_;
  std::complex<double> eta_;
};

// ------------------------------------------------------------------------------------------------
// Pure formulas (small inline functions any layer can call)
// ------------------------------------------------------------------------------------------------

// Generalised half vector of a transmission pair, Walter et al. 2007 eq. 16: normalize(etap wi +
// wo) turned to the upper hemisphere (etap = n_i / n_o). Empty if it is undefined (etap wi = -wo).
inline std::optional<Vec3> transmission_half_vector(const Vec3& wo, const Vec3& wi,
                                                    double etap) noexcept {
  Vec3 wm = etap * wi + wo;
  const double len2 = glm::dot(wm, wm);
  if (!(len2 > 0)) return std::nullopt;
  wm /= std::sqrt(len2);
  return wm.z < 0 ? -wm : wm;
}

// Half vector of a reflection pair, Walter et al. 2007 eq. 13, turned to the upper hemisphere.
inline std::optional<Vec3> reflection_half_vector(const Vec3& wo, const Vec3& wi) noexcept {
  return transmission_half_vector(wo, wi, 1.0);
}

// d(wm)/d(wi) for refraction, Walter et al. 2007 eq. 17 divided through by n_i^2:
// |wi.wm| / (wi.wm + wo.wm / etap)^2 (wi the sampled direction, etap = n_i / n_o).
inline double transmission_jacobian(double wi_dot_wm, double wo_dot_wm, double etap) noexcept {
  const double d = wi_dot_wm + wo_dot_wm / etap;
  const double d2 = d * d;
  return d2 > 0 ? std::abs(wi_dot_wm) / d2 : 0.0;
}

// Torrance-Sparrow / Walter eq. 20: F D G / (4 |cos_o| |cos_i|).
inline double microfacet_brdf(double F, double D, double G, double cos_o, double cos_i) noexcept {
  const double denom = 4.0 * std::abs(cos_o) * std::abs(cos_i);
  return denom > 0 ? F * D * G / denom : 0.0;
}

// Walter eq. 21 in Importance form: T D G |wi.wm| |wo.wm| / (|cos_i| |cos_o| (wi.wm + wo.wm /
// etap)^2), etap = n_i / n_o. The radiance BTDF is this divided by etap^2.
inline double microfacet_btdf_importance(double T, double D, double G, double wi_dot_wm,
                                         double wo_dot_wm, double cos_i, double cos_o,
                                         double etap) noexcept {
  const double d = wi_dot_wm + wo_dot_wm / etap;
  const double denom = d * d * std::abs(cos_i) * std::abs(cos_o);
  return denom > 0 ? T * D * G * std::abs(wi_dot_wm * wo_dot_wm) / denom : 0.0;
}

// ------------------------------------------------------------------------------------------------
// BxDF interface
// ------------------------------------------------------------------------------------------------

class BxDF {
 public:
  virtual ~BxDF() = default;
  virtual BxDFFlags flags() const noexcept = 0;
  // f(wo, wi); 0 for delta lobes and for impossible pairs.
  virtual double f(const Vec3& wo, const Vec3& wi, TransportMode mode) const noexcept = 0;
  // Solid-angle density with which sample() returns wi given wo (delta lobes excluded: 0).
  virtual double pdf(const Vec3& wo, const Vec3& wi) const noexcept = 0;
  // Samples wi given wo with uc (lobe choice) and u (direction), all in [0, 1). Empty when no
  // direction can be produced (total internal reflection, a sampled microfacet that sends the
  // light to the wrong side, grazing wo); this is missing mass, not an error.
  virtual std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                           TransportMode mode) const noexcept = 0;

 protected:
  BxDF() = default;
  BxDF(const BxDF&) = default;
  BxDF& operator=(const BxDF&) = default;
};

// Perfect mirror reflection with a Fresnel model: f = F(cos_o) delta(wi - reflect(wo)) / |cos_i|.
class SpecularReflection final : public BxDF {
 public:
  explicit SpecularReflection(const Fresnel& fresnel) noexcept : fresnel_(fresnel) {}
  BxDFFlags flags() const noexcept override { return BxDFFlags::Reflection | BxDFFlags::Specular; }
  double f(const Vec3&, const Vec3&, TransportMode) const noexcept override { return 0; }
  double pdf(const Vec3&, const Vec3&) const noexcept override { return 0; }
  std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                   TransportMode mode) const noexcept override;
  const Fresnel& fresnel() const noexcept { return fresnel_; }

 private:
  Fresnel fresnel_;
};

// Perfect refraction through a dielectric interface only (the reflected part is not produced):
// f = (1 - F) delta(wi - refract(wo)) / |cos_i|, times (n_o/n_i)^2 in Radiance mode. No sample
// under total internal reflection.
class SpecularTransmission final : public BxDF {
 public:
  explicit SpecularTransmission(
      double eta);  // n_inside / n_outside; DomainError outside [1e-3, 1e3]
  BxDFFlags flags() const noexcept override {
    return BxDFFlags::Transmission | BxDFFlags::Specular;
  }
  double f(const Vec3&, const Vec3&, TransportMode) const noexcept override { return 0; }
  double pdf(const Vec3&, const Vec3&) const noexcept override { return 0; }
  std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                   TransportMode mode) const noexcept override;
  double eta() const noexcept { return eta_; }

 private:
  double eta_;
};

// Smooth dielectric interface: both delta lobes; reflection is chosen with probability
// R / (R + T), R = fr_dielectric(cos_o, eta), T = 1 - R.
class SmoothDielectric final : public BxDF {
 public:
  explicit SmoothDielectric(double eta);  // n_inside / n_outside; DomainError outside [1e-3, 1e3]
  BxDFFlags flags() const noexcept override {
    return BxDFFlags::Reflection | BxDFFlags::Transmission | BxDFFlags::Specular;
  }
  double f(const Vec3&, const Vec3&, TransportMode) const noexcept override { return 0; }
  double pdf(const Vec3&, const Vec3&) const noexcept override { return 0; }
  std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                   TransportMode mode) const noexcept override;
  double eta() const noexcept { return eta_; }

 private:
  double eta_;
};

// Torrance-Sparrow microfacet reflection (Walter eq. 20 with Heitz's height-correlated G):
//   f = F(wo.wm) D(wm) G(wo, wi) / (4 |cos_o| |cos_i|),   wm = normalize(wo + wi),
// on both sides of the surface (wo and wi in the same hemisphere). Sampled by the visible normals
// of wo: pdf = D_wo(wm) / (4 |wo.wm|) (Walter eq. 14 Jacobian).
class TorranceSparrow final : public BxDF {
 public:
  TorranceSparrow(const MicrofacetDistribution& distrib, const Fresnel& fresnel) noexcept
      : distrib_(distrib), fresnel_(fresnel) {}
  BxDFFlags flags() const noexcept override { return BxDFFlags::Reflection | BxDFFlags::Glossy; }
  double f(const Vec3& wo, const Vec3& wi, TransportMode mode) const noexcept override;
  double pdf(const Vec3& wo, const Vec3& wi) const noexcept override;
  std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                   TransportMode mode) const noexcept override;
  const MicrofacetDistribution& distribution() const noexcept { return distrib_; }
  const Fresnel& fresnel() const noexcept { return fresnel_; }

 private:
  MicrofacetDistribution distrib_;
  Fresnel fresnel_;
};

// Rough dielectric interface, Walter et al. 2007:
//   reflection   f_r = F D G / (4 |cos_o| |cos_i|),           wm = normalize(wo + wi)
//   transmission f_t = (1 - F) D G |wi.wm| |wo.wm| / (|cos_i| |cos_o| (wi.wm + wo.wm / etap)^2)
//                      / etap^2 in Radiance mode,                wm = normalize(etap wi + wo)
// F = fr_dielectric(wo.wm, eta) with wm in the upper hemisphere (the sign picks the side), etap =
// n_i / n_o. Pairs whose wm is back-facing to wo or wi give 0. Sampled by the visible normals of
// wo, the lobe chosen with probability R / (R + T); the pdf includes that probability and the
// Jacobian of the half vector (Walter eqs. 14, 17).
// eta = 1 exactly (no interface) degenerates to straight transmission: a delta lobe (sample gives
// wi = -wo), f = pdf = 0.
class RoughDielectric final : public BxDF {
 public:
  RoughDielectric(const MicrofacetDistribution& distrib, double eta);  // eta as SmoothDielectric
  BxDFFlags flags() const noexcept override;
  double f(const Vec3& wo, const Vec3& wi, TransportMode mode) const noexcept override;
  double pdf(const Vec3& wo, const Vec3& wi) const noexcept override;
  std::optional<BSDFSample> sample(const Vec3& wo, double uc, const glm::dvec2& u,
                                   TransportMode mode) const noexcept override;
  const MicrofacetDistribution& distribution() const noexcept { return distrib_; }
  double eta() const noexcept { return eta_; }

 private:
  MicrofacetDistribution distrib_;
  double eta_;
};

// ------------------------------------------------------------------------------------------------
// Directional albedo
// ------------------------------------------------------------------------------------------------

// Fractions of the power arriving from direction `w_light` (unit, away from the surface) that the
// BxDF sends back to the same side (reflected) and through the surface (transmitted), with their
// standard errors. Monte Carlo over the BxDF's own sampling in Importance mode (power, not
// radiance: no (n_o/n_i)^2 factor), `samples` > 0 draws from a generator seeded with `seed`; delta
// lobes included. For a smooth dielectric the two fractions estimate F and 1 - F; for a rough
// one, reflected + transmitted <= 1 (single scattering loses what masking removes).
struct DirectionalAlbedo {
  double reflected = 0, transmitted = 0;
  double reflected_stderr = 0, transmitted_stderr = 0;
};
DirectionalAlbedo directional_albedo(const BxDF& bxdf, const Vec3& w_light, int samples,
                                     std::uint64_t seed);

}  // namespace hydrolux::optics
