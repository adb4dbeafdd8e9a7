// Tests of the BSDFs (include/hydrolux/optics/bsdf.hpp).
//
// References cited below:
//   [Walter07] B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction
//              through Rough Surfaces", EGSR 2007.
//   [Heitz14]  E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
//              JCGT 3(2), 2014.
//   [Heitz16]  E. Heitz, J. Hanika, E. d'Eon, C. Dachsbacher, "Multiple-Scattering Microfacet
//              BSDFs with the Smith Model", SIGGRAPH 2016.
//   [Veach97]  E. Veach, "Robust Monte Carlo Methods for Light Transport Simulation", PhD thesis,
//              Stanford 1997, ch. 5 (non-symmetric scattering, adjoint BSDFs).
//   [Seed003]  ../shared/seeds/003: specular BTDF with the (n_o/n_i)^2 radiance factor, and
//              f(i, o) / eta_o^2 = f(o, i) / eta_i^2.
//   [Hecht]    E. Hecht, Optics, 5th ed.: Fresnel equations (§4.6), critical angle (§4.7).
//   [pbrt4]    Pharr, Jakob, Humphreys, Physically Based Rendering 4th ed., and its bsdfs_test.cpp
//              (chi-square protocol).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "hydrolux/optics/bsdf.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/snell.hpp"
#include "support/stats.hpp"

namespace hydrolux::test {
namespace {

using optics::BSDFSample;
using optics::BxDF;
using optics::fr_dielectric;
using optics::Fresnel;
using optics::MicrofacetDistribution;
using optics::MicrofacetModel;
using optics::RoughDielectric;
using optics::SmoothDielectric;
using optics::SpecularReflection;
using optics::SpecularTransmission;
using optics::TorranceSparrow;
using optics::TransportMode;

constexpr double kWater = 1.333;
// Gold at ~600 nm (Johnson & Christy 1972, rounded): a representative conductor.
const std::complex<double> kGold(0.25, 2.98);

Vec3 direction(double theta_deg, double phi = 0.0) {
  return spherical_direction(deg_to_rad(theta_deg), phi);
}

MicrofacetDistribution distribution(MicrofacetModel model, double ax, double ay) {
  return MicrofacetDistribution::make(model, ax, ay);
}

const MicrofacetModel kModels[] = {MicrofacetModel::TrowbridgeReitz, MicrofacetModel::Beckmann};

const char* name_of(MicrofacetModel m) {
  return m == MicrofacetModel::TrowbridgeReitz ? "GGX" : "Beckmann";
}

// Relative difference, safe at 0.
double rel_diff(double a, double b) {
  const double scale = std::max(std::abs(a), std::abs(b));
  return scale > 0 ? std::abs(a - b) / scale : 0.0;
}

// ================================================================================================
// Fresnel models
// ================================================================================================

TEST(Fresnel, ModelsAndValidation) {
  // Normal incidence on a conductor: R = ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) [Hecht §4.8].
  const Fresnel gold = Fresnel::conductor(kGold);
  const double n = kGold.real(), k = kGold.imag();
  EXPECT_NEAR(gold.reflectance(1.0), (sqr(n - 1) + k * k) / (sqr(n + 1) + k * k), 1e-14);
  EXPECT_DOUBLE_EQ(gold.reflectance(-0.3), gold.reflectance(0.3));  // same from either side
  // Dielectric: ((n - 1) / (n + 1))^2 at normal incidence, from either side.
  const Fresnel water = Fresnel::dielectric(kWater);
  EXPECT_NEAR(water.reflectance(1.0), sqr((kWater - 1) / (kWater + 1)), 1e-15);
  EXPECT_NEAR(water.reflectance(-1.0), sqr((kWater - 1) / (kWater + 1)), 1e-15);
  EXPECT_EQ(water.reflectance(-0.5), 1.0);  // 60 degrees inside water: beyond the critical angle
  EXPECT_EQ(Fresnel::perfect_mirror().reflectance(0.2), 1.0);
  EXPECT_THROW(Fresnel::dielectric(0.0), DomainError);
  EXPECT_THROW(Fresnel::dielectric(std::nan("")), DomainError);
  EXPECT_THROW(Fresnel::conductor({1.0, -0.5}), DomainError);
  EXPECT_THROW(SmoothDielectric(-1.0), DomainError);
  EXPECT_THROW(RoughDielectric(distribution(MicrofacetModel::Beckmann, 0.3, 0.3), 1e6),
               DomainError);
}

// ================================================================================================
// Delta lobes
// ================================================================================================

TEST(SpecularReflection, MirrorDirectionAndFresnelWeight) {
  const SpecularReflection metal(Fresnel::conductor(kGold));
  const SpecularReflection water(Fresnel::dielectric(kWater));
  for (double theta : {0.0, 20.0, 45.0, 70.0, 89.0, 110.0, 140.0, 179.0}) {
    const Vec3 wo = direction(theta, 0.8);
    for (const SpecularReflection* b : {&metal, &water}) {
      const auto s = b->sample(wo, 0.5, {0.5, 0.5}, TransportMode::Radiance);
      ASSERT_TRUE(s.has_value());
      EXPECT_TRUE(s->is_delta);
      EXPECT_FALSE(s->is_transmission);
      EXPECT_NEAR(glm::length(s->wi - Vec3(-wo.x, -wo.y, wo.z)), 0.0, 1e-15);
      // f |cos| / pdf is the Fresnel reflectance [Seed003, specular BRDF].
      EXPECT_NEAR(s->f * std::abs(s->wi.z) / s->pdf, b->fresnel().reflectance(wo.z), 1e-14);
      EXPECT_EQ(b->f(wo, s->wi, TransportMode::Radiance), 0.0);  // delta: no density
      EXPECT_EQ(b->pdf(wo, s->wi), 0.0);
    }
  }
  EXPECT_FALSE(metal.sample(Vec3(1, 0, 0), 0.5, {0.5, 0.5}, TransportMode::Radiance));
}

TEST(SpecularTransmission, RadianceFactorSnellAndTotalInternalReflection) {
  // [Seed003]: L_o = (n_o / n_i)^2 (1 - F) L_i, so f |cos theta_i| / pdf read from sample() must
  // be (n_o / n_i)^2 (1 - F) in Radiance mode and (1 - F) in Importance mode; n_o on wo's side.
  const SpecularTransmission btdf(kWater);
  for (double theta : {0.0, 10.0, 30.0, 48.0, 60.0, 85.0, 95.0, 120.0, 150.0, 180.0}) {
    const Vec3 wo = direction(theta, 2.1);
    const bool outside = wo.z > 0;
    const double n_o = outside ? 1.0 : kWater, n_i = outside ? kWater : 1.0;
    const double F = fr_dielectric(wo.z, kWater);
    const auto rad = btdf.sample(wo, 0.3, {0.1, 0.9}, TransportMode::Radiance);
    const auto imp = btdf.sample(wo, 0.3, {0.1, 0.9}, TransportMode::Importance);
    const bool tir = !outside && std::sin(deg_to_rad(180.0 - theta)) * kWater > 1.0;
    if (tir) {
      EXPECT_FALSE(rad.has_value()) << theta;
      EXPECT_FALSE(imp.has_value()) << theta;
      continue;
    }
    ASSERT_TRUE(rad.has_value()) << theta;
    ASSERT_TRUE(imp.has_value());
    EXPECT_TRUE(rad->is_delta && rad->is_transmission);
    EXPECT_NEAR(rad->f * std::abs(rad->wi.z) / rad->pdf, sqr(n_o / n_i) * (1 - F), 1e-14);
    EXPECT_NEAR(imp->f * std::abs(imp->wi.z) / imp->pdf, 1 - F, 1e-14);
    EXPECT_NEAR(rad->eta, n_i / n_o, 1e-15);
    // Snell [Hecht §4.4]: n_o sin theta_o = n_i sin theta_i, wi on the far side, same azimuth
    // plane (opposite azimuth direction).
    const double sin_o = std::sqrt(sqr(wo.x) + sqr(wo.y));
    const double sin_i = std::sqrt(sqr(rad->wi.x) + sqr(rad->wi.y));
    EXPECT_NEAR(n_o * sin_o, n_i * sin_i, 1e-14);
    EXPECT_LT(rad->wi.z * wo.z, 0.0);
    EXPECT_LE(rad->wi.x * wo.x + rad->wi.y * wo.y, 1e-15);
  }
}

TEST(SmoothDielectric, ReflectancePlusTransmittanceIsOne) {
  // R from the reflection lobe (f |cos| = R) and T from the transmission lobe (Importance mode:
  // f |cos| = T) at many angles from both sides; R + T = 1 to rounding, each checked against
  // fresnel_dielectric's amplitude-based R and T, which are computed independently of
  // fr_dielectric [Hecht eqs. 4.34-4.41].
  const SmoothDielectric smooth(kWater);
  const double critical = rad_to_deg(std::asin(1.0 / kWater));  // 48.6 degrees [Hecht §4.7]
  for (int i = 0; i <= 180; ++i) {
    const double theta = i * 1.0 - (i == 90 ? 0.5 : 0.0);  // skip exactly grazing
    const Vec3 wo = direction(theta, 0.3);
    const bool outside = wo.z > 0;
    const auto refl = smooth.sample(wo, 0.0, {0.5, 0.5}, TransportMode::Importance);
    ASSERT_TRUE(refl.has_value()) << theta;
    ASSERT_FALSE(refl->is_transmission);
    const double R = refl->f * std::abs(refl->wi.z);
    const auto ref = outside ? optics::fresnel_dielectric(wo.z, 1.0, kWater)
                             : optics::fresnel_dielectric(-wo.z, kWater, 1.0);
    EXPECT_NEAR(R, ref.R, 1e-13) << theta;
    EXPECT_NEAR(refl->pdf, R, 1e-15);  // probability R / (R + T) = R
    const double theta_inside = 180.0 - theta;
    if (!outside && theta_inside > critical) {
      EXPECT_NEAR(R, 1.0, 1e-15) << "TIR at " << theta_inside;
      const auto none = smooth.sample(wo, 0.999999, {0.5, 0.5}, TransportMode::Importance);
      ASSERT_TRUE(none.has_value());  // still the reflection lobe: T = 0
      EXPECT_FALSE(none->is_transmission);
      continue;
    }
    const auto tran =
        smooth.sample(wo, std::nextafter(1.0, 0.0), {0.5, 0.5}, TransportMode::Importance);
    ASSERT_TRUE(tran.has_value()) << theta;
    ASSERT_TRUE(tran->is_transmission);
    const double T = tran->f * std::abs(tran->wi.z);
    EXPECT_NEAR(T, ref.T, 1e-13) << theta;
    EXPECT_NEAR(R + T, 1.0, 1e-14) << theta;
    EXPECT_NEAR(tran->pdf, T, 1e-15);
    // Radiance mode differs by exactly (n_o / n_i)^2 [Seed003].
    const auto tran_rad =
        smooth.sample(wo, std::nextafter(1.0, 0.0), {0.5, 0.5}, TransportMode::Radiance);
    ASSERT_TRUE(tran_rad.has_value());
    const double n_o = outside ? 1.0 : kWater, n_i = outside ? kWater : 1.0;
    EXPECT_NEAR(tran_rad->f / tran->f, sqr(n_o / n_i), 1e-14);
  }
}

TEST(SmoothDielectric, CriticalAngleOfWater) {
  // From water into air the critical angle is asin(1 / 1.333) = 48.61 degrees [Hecht §4.7]: just
  // below it light still refracts out, just above it the sampler only reflects.
  const SmoothDielectric smooth(kWater);
  const SpecularTransmission btdf(kWater);
  const double critical = std::asin(1.0 / kWater);
  EXPECT_NEAR(rad_to_deg(critical), 48.61, 0.005);
  const Vec3 below = spherical_direction(kPi<double> - (critical - 1e-4), 0.0);  // inside water
  const Vec3 above = spherical_direction(kPi<double> - (critical + 1e-4), 0.0);
  EXPECT_TRUE(btdf.sample(below, 0.5, {0.5, 0.5}, TransportMode::Radiance).has_value());
  EXPECT_FALSE(btdf.sample(above, 0.5, {0.5, 0.5}, TransportMode::Radiance).has_value());
  const auto t =
      smooth.sample(below, std::nextafter(1.0, 0.0), {0.5, 0.5}, TransportMode::Radiance);
  ASSERT_TRUE(t.has_value());
  EXPECT_TRUE(t->is_transmission);
  EXPECT_GT(t->wi.z, 0.0);
  EXPECT_LT(t->wi.z, 0.03);  // leaves almost grazing
  const auto r =
      smooth.sample(above, std::nextafter(1.0, 0.0), {0.5, 0.5}, TransportMode::Radiance);
  ASSERT_TRUE(r.has_value());
  EXPECT_FALSE(r->is_transmission);
  EXPECT_EQ(r->pdf, 1.0);
}

// ================================================================================================
// A catalogue of BxDFs for the generic checks
// ================================================================================================

struct Named {
  std::string name;
  std::shared_ptr<const BxDF> bxdf;
};

std::vector<Named> catalogue(bool with_delta) {
  std::vector<Named> v;
  for (MicrofacetModel model : kModels) {
    const std::string m = name_of(model);
    for (auto [ax, ay] : {std::pair{1e-4, 1e-4}, std::pair{0.05, 0.05}, std::pair{0.3, 0.3},
                          std::pair{0.1, 0.6}, std::pair{1.0, 1.0}, std::pair{2.5, 0.7}}) {
      const auto d = distribution(model, ax, ay);
      const std::string a = " alpha " + std::to_string(ax) + "," + std::to_string(ay);
      v.push_back({"TS " + m + " gold" + a,
                   std::make_shared<TorranceSparrow>(d, Fresnel::conductor(kGold))});
      v.push_back({"TS " + m + " water" + a,
                   std::make_shared<TorranceSparrow>(d, Fresnel::dielectric(kWater))});
      v.push_back({"TS " + m + " mirror" + a,
                   std::make_shared<TorranceSparrow>(d, Fresnel::perfect_mirror())});
      v.push_back({"Rough " + m + " 1.333" + a, std::make_shared<RoughDielectric>(d, kWater)});
      v.push_back(
          {"Rough " + m + " 1/1.333" + a, std::make_shared<RoughDielectric>(d, 1.0 / kWater)});
    }
    v.push_back({"Rough " + m + " eta 1",
                 std::make_shared<RoughDielectric>(distribution(model, 0.3, 0.3), 1.0)});
  }
  if (with_delta) {
    v.push_back({"SpecularReflection gold",
                 std::make_shared<SpecularReflection>(Fresnel::conductor(kGold))});
    v.push_back({"SpecularTransmission", std::make_shared<SpecularTransmission>(kWater)});
    v.push_back({"SmoothDielectric", std::make_shared<SmoothDielectric>(kWater)});
    v.push_back({"SmoothDielectric 1/1.333", std::make_shared<SmoothDielectric>(1 / kWater)});
  }
  return v;
}

// Awkward directions: exact poles, exact and nearly grazing, both sides, random.
std::vector<Vec3> awkward_directions() {
  std::vector<Vec3> ws = {Vec3(0, 0, 1),
                          Vec3(0, 0, -1),
                          Vec3(1, 0, 0),
                          Vec3(0, -1, 0),
                          Vec3(1, 0, 1e-300),
                          Vec3(0.6, 0.8, -1e-300),
                          glm::normalize(Vec3(1, 1, 1e-8)),
                          glm::normalize(Vec3(-1, 0.3, -1e-8)),
                          direction(48.6),
                          direction(180 - 48.6),
                          direction(180 - 48.61)};
  Rng rng(99);
  for (int i = 0; i < 12; ++i) ws.push_back(uniform_sphere(rng.uniform(), rng.uniform()));
  return ws;
}

TEST(Bsdf, NoNaNOrInfinityAnywhere) {
  // Every pair of awkward directions, both modes, and samples for u at the ends of [0, 1).
  const std::vector<Vec3> ws = awkward_directions();
  const double us[] = {0.0, 1e-12, 0.5, 1.0 - 1e-12, std::nextafter(1.0, 0.0)};
  for (const Named& b : catalogue(true)) {
    for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
      for (const Vec3& wo : ws) {
        for (const Vec3& wi : ws) {
          const double f = b.bxdf->f(wo, wi, mode);
          const double p = b.bxdf->pdf(wo, wi);
          ASSERT_TRUE(std::isfinite(f) && f >= 0) << b.name << " f " << f;
          ASSERT_TRUE(std::isfinite(p) && p >= 0) << b.name << " pdf " << p;
        }
        for (double uc : us) {
          for (double u1 : us) {
            for (double u2 : {0.0, 0.3, std::nextafter(1.0, 0.0)}) {
              const auto s = b.bxdf->sample(wo, uc, {u1, u2}, mode);
              if (!s) continue;
              ASSERT_TRUE(std::isfinite(s->f) && s->f >= 0) << b.name;
              ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0) << b.name;
              ASSERT_NEAR(glm::length(s->wi), 1.0, 1e-12) << b.name;
              ASSERT_TRUE(std::isfinite(s->eta) && s->eta > 0) << b.name;
            }
          }
        }
      }
    }
  }
}

TEST(Bsdf, SampleAgreesWithEvalAndPdf) {
  // sample() must return the same f and pdf that f() and pdf() give for the direction it returns
  // (consistency that MIS relies on), and flag transmission and eta truthfully. Relative
  // tolerance 1e-9: the only difference is the half vector rebuilt from (wo, wi) in f()/pdf().
  Rng rng(7);
  for (const Named& b : catalogue(false)) {
    if (has_flag(b.bxdf->flags(), optics::BxDFFlags::Specular)) continue;
    if (b.name.find("alpha 0.0001") != std::string::npos) continue;  // lobes too sharp for 1e-9
    int valid = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3 wo = uniform_sphere(rng.uniform(), rng.uniform());
      const TransportMode mode = i % 2 ? TransportMode::Radiance : TransportMode::Importance;
      const double uc = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
      const auto s = b.bxdf->sample(wo, uc, {u1, u2}, mode);
      if (!s) continue;
      ++valid;
      EXPECT_FALSE(s->is_delta);
      EXPECT_EQ(s->is_transmission, s->wi.z * wo.z < 0) << b.name;
      EXPECT_LT(rel_diff(s->f, b.bxdf->f(wo, s->wi, mode)), 1e-9) << b.name;
      EXPECT_LT(rel_diff(s->pdf, b.bxdf->pdf(wo, s->wi)), 1e-9) << b.name;
      if (s->is_transmission) {
        const double eta = dynamic_cast<const RoughDielectric&>(*b.bxdf).eta();
        EXPECT_DOUBLE_EQ(s->eta, wo.z > 0 ? eta : 1.0 / eta);
      } else {
        EXPECT_EQ(s->eta, 1.0);
      }
    }
    EXPECT_GT(valid, 500) << b.name;  // the samplers mostly succeed (least at alpha 2.5)
  }
}

// ================================================================================================
// Chi-square of every non-delta sampler against its pdf
// ================================================================================================

struct ChiCase {
  const char* what;
  bool rough_dielectric;  // else Torrance-Sparrow
  MicrofacetModel model;
  double ax, ay;
  double eta;  // RoughDielectric eta or TS dielectric eta; 0: TS with the gold conductor
  double theta_deg, phi;
};

const ChiCase kChiCases[] = {
    {"TS GGX gold", false, MicrofacetModel::TrowbridgeReitz, 0.3, 0.3, 0.0, 45.0, 0.0},
    {"TS GGX water aniso", false, MicrofacetModel::TrowbridgeReitz, 0.1, 0.4, kWater, 70.0, 1.0},
    {"TS GGX water from inside", false, MicrofacetModel::TrowbridgeReitz, 0.5, 0.5, kWater, 150.0,
     0.4},
    {"TS GGX gold rough grazing", false, MicrofacetModel::TrowbridgeReitz, 1.0, 1.0, 0.0, 80.0,
     0.5},
    {"TS Beckmann gold aniso", false, MicrofacetModel::Beckmann, 0.5, 0.2, 0.0, 20.0, 2.0},
    {"TS Beckmann water", false, MicrofacetModel::Beckmann, 0.1, 0.1, kWater, 60.0, 0.0},
    {"Rough GGX 1.333 outside", true, MicrofacetModel::TrowbridgeReitz, 0.1, 0.1, kWater, 30.0,
     0.0},
    {"Rough GGX 1.333 inside", true, MicrofacetModel::TrowbridgeReitz, 0.4, 0.4, kWater, 140.0,
     1.0},
    {"Rough GGX 1.333 inside past critical", true, MicrofacetModel::TrowbridgeReitz, 0.3, 0.3,
     kWater, 120.0, 0.2},
    {"Rough GGX 1/1.333 outside aniso", true, MicrofacetModel::TrowbridgeReitz, 0.2, 0.5,
     1 / kWater, 60.0, 0.7},
    {"Rough GGX 1/1.333 inside", true, MicrofacetModel::TrowbridgeReitz, 0.7, 0.7, 1 / kWater,
     170.0, 3.0},
    {"Rough Beckmann 1.333 outside", true, MicrofacetModel::Beckmann, 0.1, 0.1, kWater, 30.0, 0.0},
    {"Rough Beckmann 1.333 inside past critical", true, MicrofacetModel::Beckmann, 0.3, 0.3, kWater,
     120.0, 0.2},
    {"Rough Beckmann 1/1.333 outside aniso", true, MicrofacetModel::Beckmann, 0.2, 0.5, 1 / kWater,
     60.0, 0.7},
    {"Rough Beckmann 1/1.333 inside", true, MicrofacetModel::Beckmann, 0.7, 0.7, 1 / kWater, 170.0,
     3.0},
};
constexpr int kChiRuns = static_cast<int>(std::size(kChiCases));

std::unique_ptr<BxDF> make_bxdf(const ChiCase& c) {
  const auto d = distribution(c.model, c.ax, c.ay);
  if (c.rough_dielectric) return std::make_unique<RoughDielectric>(d, c.eta);
  const Fresnel fresnel = c.eta > 0 ? Fresnel::dielectric(c.eta) : Fresnel::conductor(kGold);
  return std::make_unique<TorranceSparrow>(d, fresnel);
}

class BsdfChiSquare : public ::testing::TestWithParam<int> {};

TEST_P(BsdfChiSquare, SamplerMatchesPdf) {
  // [pbrt4] protocol: 80 x 160 (theta, phi) cells, 1e6 samples, expected counts from the pdf
  // integrated per cell, cells with E < 5 pooled; family-wise 1 % over this table (Sidak).
  const ChiCase& c = kChiCases[GetParam()];
  const auto bxdf = make_bxdf(c);
  const Vec3 wo = direction(c.theta_deg, c.phi);
  ChiSquareConfig config;
  config.seed = 2000 + static_cast<std::uint64_t>(GetParam());
  const ChiSquareResult r = chi_square_bxdf(*bxdf, wo, config);
  EXPECT_GT(r.p_value, sidak_alpha(0.01, kChiRuns)) << c.what << ": " << r.describe();
  // Failed samples (reflected or refracted to the wrong side, TIR on a microfacet that had been
  // given to transmission) are the pdf's missing mass: the failure rate must match 1 - int pdf.
  // Tolerance: 5 binomial standard errors plus the quadrature's 1e-4.
  const double fail_rate = static_cast<double>(r.failures) / static_cast<double>(r.samples);
  const double missing = 1.0 - r.pdf_integral;
  const double se = std::sqrt(std::max(missing, 1e-6) / static_cast<double>(r.samples));
  EXPECT_NEAR(fail_rate, missing, 5 * se + 1e-4) << c.what << ": " << r.describe();
}

INSTANTIATE_TEST_SUITE_P(Table, BsdfChiSquare, ::testing::Range(0, kChiRuns));

// ================================================================================================
// Reciprocity
// ================================================================================================

TEST(Reciprocity, BrdfsAreSymmetric) {
  // Helmholtz reciprocity of every BRDF here: f(wo, wi) = f(wi, wo) for pairs on the same side
  // (Torrance-Sparrow and the rough dielectric's reflection lobe: F(wo.wm) = F(wi.wm) and D, G
  // are symmetric under the swap). Relative tolerance 1e-12 (rounding only).
  Rng rng(3);
  for (const Named& b : catalogue(false)) {
    if (has_flag(b.bxdf->flags(), optics::BxDFFlags::Specular)) continue;
    int nonzero = 0;
    for (int i = 0; i < 500; ++i) {
      Vec3 wo = uniform_sphere(rng.uniform(), rng.uniform());
      Vec3 wi = uniform_sphere(rng.uniform(), rng.uniform());
      if (wo.z * wi.z < 0) wi.z = -wi.z;  // same side
      const double a = b.bxdf->f(wo, wi, TransportMode::Radiance);
      const double c = b.bxdf->f(wi, wo, TransportMode::Radiance);
      nonzero += a > 0;
      EXPECT_LT(rel_diff(a, c), 1e-12) << b.name;
    }
    if (b.name.find("alpha 0.0001") == std::string::npos &&
        b.name.find("eta 1") == std::string::npos) {
      EXPECT_GT(nonzero, 100) << b.name;
    }
  }
}

TEST(Reciprocity, RoughDielectricBtdfGeneralised) {
  // [Seed003], [Walter07] §5.3, [Veach97] §5.2: the radiance BTDF obeys
  //   f(wo, wi) / n_o^2 = f(wi, wo) / n_i^2      (n_o on wo's side, n_i on wi's side),
  // and the Importance-mode BTDF is its adjoint, f_imp(wo, wi) = f_rad(wi, wo). Note that the
  // Importance BTDF is therefore NOT symmetric either: f_imp(wo, wi) / n_i^2 = f_imp(wi, wo) /
  // n_o^2 (it differs from f_rad by etap^2 = (n_i / n_o)^2, which inverts under the swap).
  // Pairs come from the sampler (so that most have f > 0) and from uniform directions.
  // Relative tolerance 1e-6: f(wo, wi) evaluates F at wo.wm and f(wi, wo) at wi.wm, equal in exact
  // arithmetic; but a pair that meets the microfacet at grazing on the air side (cos ~ 1e-4) meets
  // it at the critical angle on the water side, where T = 1 - F has an infinite slope, and the
  // 1e-16 rounding of wm becomes up to ~1e-8 relative in T (measured: < 5e-9). Elsewhere the
  // agreement is ~1e-14.
  Rng rng(4);
  for (MicrofacetModel model : kModels) {
    for (double eta : {kWater, 1.0 / kWater}) {
      for (auto [ax, ay] : {std::pair{0.1, 0.1}, std::pair{0.5, 0.5}, std::pair{0.2, 0.8}}) {
        const RoughDielectric bsdf(distribution(model, ax, ay), eta);
        int tested = 0;
        for (int i = 0; i < 2000; ++i) {
          const Vec3 wo = uniform_sphere(rng.uniform(), rng.uniform());
          Vec3 wi;
          if (i % 2 == 0) {
            const double uc = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
            const auto s = bsdf.sample(wo, uc, {u1, u2}, TransportMode::Radiance);
            if (!s || !s->is_transmission) continue;
            wi = s->wi;
          } else {
            wi = uniform_sphere(rng.uniform(), rng.uniform());
            if (wi.z * wo.z > 0) wi.z = -wi.z;
          }
          const double n_o = wo.z > 0 ? 1.0 : eta, n_i = wi.z > 0 ? 1.0 : eta;
          const double rad_oi = bsdf.f(wo, wi, TransportMode::Radiance);
          const double rad_io = bsdf.f(wi, wo, TransportMode::Radiance);
          const double imp_oi = bsdf.f(wo, wi, TransportMode::Importance);
          const double imp_io = bsdf.f(wi, wo, TransportMode::Importance);
          EXPECT_LT(rel_diff(rad_oi / sqr(n_o), rad_io / sqr(n_i)), 1e-6);
          EXPECT_LT(rel_diff(imp_oi, rad_io), 1e-6);
          EXPECT_LT(rel_diff(imp_oi / sqr(n_i), imp_io / sqr(n_o)), 1e-6);
          tested += rad_oi > 0;
        }
        EXPECT_GT(tested, 500) << name_of(model) << " eta " << eta;
      }
    }
  }
}

// ================================================================================================
// Energy: white furnace
// ================================================================================================

TEST(Furnace, RoughBsdfsDoNotCreateEnergy) {
  // In Importance mode the directional albedo int f(wo, wi) |cos theta_i| dwi is the fraction of
  // the energy arriving along wo that is scattered: it must not exceed 1. Estimated with the
  // BSDF's own sampling (2e4 samples; the weights f |cos| / pdf = G / G1 lie in [0, 1], so the
  // noise is small); asserted <= 1 + 3 standard errors (+ 1e-12 for rounding when every weight
  // is 1). The same integral with uniform sphere sampling, which does not use sample() or pdf(),
  // must agree within 4 combined standard errors: that catches directions where f > 0 but the
  // sampler never goes (pdf = 0). Only for alpha >= 0.3, where the uniform estimate has a usable
  // variance.
  struct Case {
    const char* what;
    std::shared_ptr<const BxDF> bxdf;
    MicrofacetDistribution d;
  };
  std::vector<Case> cases;
  for (MicrofacetModel model : kModels) {
    for (double alpha : {0.05, 0.3, 1.0}) {
      const auto d = distribution(model, alpha, alpha);
      cases.push_back(
          {"TS gold", std::make_shared<TorranceSparrow>(d, Fresnel::conductor(kGold)), d});
      cases.push_back(
          {"TS water", std::make_shared<TorranceSparrow>(d, Fresnel::dielectric(kWater)), d});
      cases.push_back({"Rough 1.333", std::make_shared<RoughDielectric>(d, kWater), d});
      cases.push_back({"Rough 1/1.333", std::make_shared<RoughDielectric>(d, 1 / kWater), d});
    }
    const auto aniso = distribution(model, 0.3, 0.9);
    cases.push_back({"Rough aniso", std::make_shared<RoughDielectric>(aniso, kWater), aniso});
  }
  std::uint64_t seed = 100;
  for (const Case& c : cases) {
    for (double theta : {0.0, 40.0, 75.0, 110.0, 160.0}) {
      const Vec3 wo = direction(theta, 0.6);
      const Estimate e = integrate_f_cos(*c.bxdf, wo, TransportMode::Importance, 20'000, ++seed);
      EXPECT_LE(e.mean, 1.0 + 3 * e.std_error + 1e-12)
          << c.what << " " << name_of(c.d.model()) << " alpha " << c.d.alpha_x() << " theta "
          << theta << ": " << e.mean << " +- " << e.std_error;
      EXPECT_GT(e.mean, 0.0);
      if (c.d.alpha_x() >= 0.3) {
        const Estimate u =
            integrate_f_cos_uniform(*c.bxdf, wo, TransportMode::Importance, 40'000, ++seed);
        EXPECT_NEAR(e.mean, u.mean, 4 * std::hypot(e.std_error, u.std_error))
            << c.what << " " << name_of(c.d.model()) << " alpha " << c.d.alpha_x() << " theta "
            << theta;
      }
    }
  }
}

TEST(Furnace, MirrorMicrofacetsLoseEnergyOnlyWhenRough) {
  // Torrance-Sparrow with F = 1 (a perfect mirror, or a conductor with a huge k): a single-
  // scattering microfacet model loses the light that would scatter more than once on the
  // microsurface, 1 - E[G(wo, wi) / G1(wo)], including the light a microfacet reflects below the
  // horizon [Heitz16, §1 and Fig. 1]. It vanishes as alpha -> 0. At normal incidence the part
  // reflected below the horizon alone is P(theta_m > 45 deg), = alpha^2 / (1 + alpha^2) for GGX
  // (its slope tail is heavy): 1.0 % at alpha = 0.1; Beckmann's Gaussian tail loses far less.
  // Bounds (lower bounds on the albedo, 2e4 samples, weights in [0, 1]), set from the measured
  // GGX albedos with about a fifth of the loss as margin:
  //   alpha  theta_o:   0     30    60    80      measured GGX:  0      30     60     80
  //   0.01            0.997 0.997 0.997 0.995                  0.9999 0.9998 0.9997 0.9980
  //   0.05            0.995 0.995 0.99  0.94                   0.9971 0.9966 0.9926 0.9537
  //   0.1             0.985 0.98  0.96  0.87                   0.9881 0.9860 0.9695 0.8961
  // At alpha = 1 the loss is large: the albedo kept is GGX 0.31, Beckmann 0.46 at normal incidence: < 0.6.
  const double alphas[] = {0.01, 0.05, 0.1};
  const double thetas[] = {0.0, 30.0, 60.0, 80.0};
  const double bounds[3][4] = {
      {0.997, 0.997, 0.997, 0.995}, {0.995, 0.995, 0.99, 0.94}, {0.985, 0.98, 0.96, 0.87}};
  for (MicrofacetModel model : kModels) {
    for (const Fresnel& fresnel : {Fresnel::perfect_mirror(), Fresnel::conductor({1.0, 1e5})}) {
      std::uint64_t seed = 300;
      for (int a = 0; a < 3; ++a) {
        const TorranceSparrow ts(distribution(model, alphas[a], alphas[a]), fresnel);
        for (int t = 0; t < 4; ++t) {
          const Estimate e =
              integrate_f_cos(ts, direction(thetas[t]), TransportMode::Importance, 20'000, ++seed);
          EXPECT_GE(e.mean, bounds[a][t])
              << name_of(model) << " alpha " << alphas[a] << " theta " << thetas[t];
          EXPECT_LE(e.mean, 1.0 + 3 * e.std_error + 1e-12);
        }
      }
      const TorranceSparrow rough(distribution(model, 1.0, 1.0), fresnel);
      const Estimate e =
          integrate_f_cos(rough, direction(0.0), TransportMode::Importance, 20'000, 9);
      EXPECT_LT(e.mean, 0.6) << name_of(model);
    }
  }
}

TEST(Furnace, RoughDielectricApproachesSmoothAsAlphaShrinks) {
  // As alpha -> 0 the rough interface becomes the smooth one: the transmitted albedo (Importance
  // mode, wi on the far side) tends to 1 - F(theta_o) and the reflected one to F. With alpha =
  // 1e-3 the microfacet normals stay within ~0.1 degree of the macro normal, so F(wo.wm) differs
  // from F(theta_o) by < 1e-5 on average (F is smooth away from the critical angle, and the
  // first-order term averages out), and the masking loss 1 - G/G1 is < 1e-6 below 85 degrees.
  // What remains is Monte Carlo noise: each sample weighs ~0 or ~1, standard error sqrt(T(1 - T)/
  // N). Tolerance: 4 standard errors + 2e-5.
  const std::int64_t n = 100'000;
  std::uint64_t seed = 500;
  for (MicrofacetModel model : kModels) {
    const RoughDielectric rough(distribution(model, 1e-3, 1e-3), kWater);
    // Outside (air -> water) and inside (water -> air, kept below the critical angle 48.6).
    for (double theta : {0.0, 30.0, 60.0, 80.0, 180.0, 160.0, 140.0}) {
      const Vec3 wo = direction(theta, 0.9);
      const double R = fr_dielectric(wo.z, kWater);
      const double se = std::sqrt(R * (1 - R) / static_cast<double>(n));
      const Estimate t = integrate_f_cos(rough, wo, TransportMode::Importance, n, ++seed,
                                         Hemisphere::Transmission);
      const Estimate r =
          integrate_f_cos(rough, wo, TransportMode::Importance, n, ++seed, Hemisphere::Reflection);
      EXPECT_NEAR(t.mean, 1 - R, 4 * se + 2e-5) << name_of(model) << " theta " << theta;
      EXPECT_NEAR(r.mean, R, 4 * se + 2e-5) << name_of(model) << " theta " << theta;
      // Radiance mode carries (n_o / n_i)^2 on the transmitted part, like the smooth BTDF. Same
      // seed, so the same samples: the ratio is exact up to rounding.
      if (theta == 30.0 || theta == 160.0) {
        const Estimate tr = integrate_f_cos(rough, wo, TransportMode::Radiance, n, seed - 1,
                                            Hemisphere::Transmission);
        const double n_o = wo.z > 0 ? 1.0 : kWater, n_i = wo.z > 0 ? kWater : 1.0;
        EXPECT_NEAR(tr.mean / t.mean, sqr(n_o / n_i), 1e-12);
      }
    }
  }
}

TEST(RoughDielectric, IndexMatchedInterfaceIsStraightThrough) {
  // eta = 1: no interface; all light continues along -wo (a delta), nothing has a density.
  const RoughDielectric matched(distribution(MicrofacetModel::TrowbridgeReitz, 0.3, 0.3), 1.0);
  for (double theta : {0.0, 45.0, 89.0, 135.0}) {
    const Vec3 wo = direction(theta, 1.0);
    const auto s = matched.sample(wo, 0.2, {0.3, 0.4}, TransportMode::Radiance);
    ASSERT_TRUE(s.has_value());
    EXPECT_TRUE(s->is_delta && s->is_transmission);
    EXPECT_NEAR(glm::length(s->wi + wo), 0.0, 1e-15);
    EXPECT_NEAR(s->f * std::abs(s->wi.z) / s->pdf, 1.0, 1e-15);
    EXPECT_EQ(matched.f(wo, -wo, TransportMode::Radiance), 0.0);
  }
}

// The library's directional albedo: a smooth dielectric splits power into F and 1 - F (Fresnel,
// air to water at 30 and 70 degrees), within 5 standard errors of the Bernoulli lobe choice; a rough
// one conserves energy and agrees with the test harness's independent integral.
TEST(DirectionalAlbedo, SmoothSplitsFresnelAndRoughConserves) {
  const SmoothDielectric smooth(kWater);
  for (double theta : {30.0, 70.0}) {
    const Vec3 w = direction(theta, 1.0);
    const double F = fr_dielectric(w.z, kWater);
    const auto a = optics::directional_albedo(smooth, w, 100000, 11);
    const double sigma = std::sqrt(F * (1 - F) / 100000);
    EXPECT_NEAR(a.reflected, F, 5 * sigma) << theta;
    EXPECT_NEAR(a.transmitted, 1 - F, 5 * sigma) << theta;
    EXPECT_NEAR(a.reflected + a.transmitted, 1.0, 1e-12);
  }
  const RoughDielectric rough(distribution(MicrofacetModel::TrowbridgeReitz, 0.3, 0.3), kWater);
  const Vec3 w = direction(60.0, 1.0);
  const auto a = optics::directional_albedo(rough, w, 200000, 12);
  EXPECT_LE(a.reflected + a.transmitted, 1.0 + 3 * (a.reflected_stderr + a.transmitted_stderr));
  const auto r = integrate_f_cos(rough, w, TransportMode::Importance, 200000, 99, Hemisphere::Reflection);
  const auto t = integrate_f_cos(rough, w, TransportMode::Importance, 200000, 98, Hemisphere::Transmission);
  EXPECT_NEAR(a.reflected, r.mean, 5 * std::hypot(a.reflected_stderr, r.std_error));
  EXPECT_NEAR(a.transmitted, t.mean, 5 * std::hypot(a.transmitted_stderr, t.std_error));
  EXPECT_THROW((void)optics::directional_albedo(rough, w, 0, 1), DomainError);
}

}  // namespace
}  // namespace hydrolux::test
