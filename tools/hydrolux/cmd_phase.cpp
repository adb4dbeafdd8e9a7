// hydrolux phase: scattered intensity against angle for one drop, by the theory of one's choice.
#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <optional>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/geometric.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "hydrolux/scatter/theories.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {
// The numbers are scatter/params.hpp's; the theory, the drops, the light, the media, the angles
// and the output are this command's.
struct PhaseArgs {
  std::shared_ptr<scatter::PhaseRequest> r = std::make_shared<scatter::PhaseRequest>();
  std::string theory = "mie";
  std::optional<double> radius_um;
  double wavelength_nm = 0;
  std::string distribution = "mono";
  std::string medium = "water", surrounding = "air";
  std::string angles = "0:180:181";
  bool csv = false;
  bool quiet = false;
};

// Marshall-Palmer rain is averaged over drops of these radii (smaller ones scatter little light
// and larger ones break up).
constexpr double kRainMinRadiusUm = 50, kRainMaxRadiusUm = 3000;

// --size-distribution: mono | gamma:W | lognormal:W | marshall-palmer:H. Returns the quadrature
// over radius and a description.
std::pair<scatter::RadiusQuadrature, std::string> size_quadrature(const PhaseArgs& a) {
  using scatter::SizeDistributionKind;
  scatter::SizeDistributionSpec spec;
  try {
    spec = scatter::parse_size_distribution(a.distribution);
  } catch (const Error& e) {
    throw Error(fmt::format("--size-distribution {}", e.what()));
  }
  if (spec.kind == SizeDistributionKind::marshall_palmer) {
    const auto d = scatter::SizeDistribution::marshall_palmer(spec.parameter);
    return {d.quadrature(a.r->nodes, kRainMinRadiusUm * 1e-6, kRainMaxRadiusUm * 1e-6),
            fmt::format("Marshall-Palmer rain, {:g} mm/h, radii {:g}-{:g} um", spec.parameter, kRainMinRadiusUm,
                        kRainMaxRadiusUm)};
  }
  if (!a.radius_um) throw Error("--radius-um is required (the mean radius for gamma and lognormal)");
  const double r = *a.radius_um * 1e-6;
  if (spec.kind == SizeDistributionKind::monodisperse)
    return {scatter::SizeDistribution::monodisperse(r).quadrature(1), fmt::format("radius {:g} um", *a.radius_um)};
  const bool gamma = spec.kind == SizeDistributionKind::gamma;
  const auto d = gamma ? scatter::SizeDistribution::gamma(r, spec.parameter)
                       : scatter::SizeDistribution::log_normal(r, spec.parameter);
  // Gauss-Legendre over a range holding the number and r^4-weighted tails: Mie intensities
  // oscillate in r, which a range rule with enough nodes resolves (a Gaussian rule of n(r) would
  // alias).
  return {scatter::intensity_quadrature(d, a.r->nodes),
          fmt::format("{} distribution, mean radius {:g} um, relative width {:g}, {} radii",
                      gamma ? "gamma" : "lognormal", *a.radius_um, spec.parameter, a.r->nodes)};
}
int run_phase(const PhaseArgs& a) {
  scatter::Theory theory;
  try {
    theory = scatter::parse_theory(a.theory);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("--theory: {}", e.what()));
  }
  const auto sphere = medium_flag("--medium", a.medium);
  const auto outside = medium_flag("--surrounding", a.surrounding);
  check_temperature_flag(a.r->temperature_c, {sphere.get(), outside.get()});
  const auto angles = parse_angles_deg(a.angles, "--angles-deg");
  std::vector<double> theta(angles.size());
  for (std::size_t i = 0; i < theta.size(); ++i) theta[i] = deg_to_rad(angles[i]);
  const auto [quadrature, drops] = size_quadrature(a);
  // Check the media at this wavelength first, so a bad --wavelength-nm fails before any work.
  const auto p = scatter::sphere_problem(quadrature.radius_m.front() * 1e6, a.wavelength_nm, *sphere, *outside,
                                         a.r->temperature_c);
  ProgressBar bar("phase", a.quiet || quadrature.size() < 2);
  const auto result = scatter::average_intensities(theory, quadrature, a.wavelength_nm, *sphere, *outside,
                                                   a.r->temperature_c, theta, a.r->threads, bar.callback());
  bar.finish();
  std::optional<scatter::MuellerElements> mm;
  if (a.r->mueller) mm = scatter::mueller_elements(result);

  if (a.csv) {
    fmt::print("theta_deg,i1,i2,i{}\n", mm ? ",s11,s12,s33,s34" : "");
  } else {
    fmt::print("# theory {}, {}, wavelength {:g} nm: m = {:.6g}{:+.3g}i{}\n", scatter::theory_name(theory), drops,
               a.wavelength_nm, p.m.real(), p.m.imag(),
               quadrature.size() == 1 ? fmt::format(", x = {:.6g}", p.x) : std::string());
    if (quadrature.size() > 1) fmt::print("# number-weighted mean over {} radii\n", quadrature.size());
    if (theory.kind == scatter::TheoryKind::Airy)
      fmt::print("# Airy theory approximates order {} near its rainbow angle {:.2f} deg only (within a few "
                 "degrees for x ~ 1000, less for larger drops); use mie or debye:{} elsewhere\n",
                 theory.p, rad_to_deg(scatter::rainbow_angle(p.m.real(), theory.p)), theory.p);
    if (theory.kind == scatter::TheoryKind::Geometric && p.x < 100)
      fmt::print("# geometric optics needs x >> 1 (here x = {:.3g}); use mie\n", p.x);
    fmt::print("# i1 = |S1|^2 (perpendicular), i2 = |S2|^2 (parallel), i = (i1 + i2) / 2 "
               "(Bohren & Huffman normalisation)\n");
    if (mm)
      fmt::print("# Mueller elements S11 = (i2 + i1) / 2, S12 = (i2 - i1) / 2, S33 = Re <S2 S1*>, S34 = Im <S2 S1*> "
                 "(Bohren & Huffman eq. 4.77)\n");
    fmt::print("{:>10}  {:>16}  {:>16}  {:>16}{}\n", "theta_deg", "i1", "i2", "i",
               mm ? fmt::format("  {:>16}  {:>16}  {:>16}  {:>16}", "S11", "S12", "S33", "S34") : std::string());
  }
  for (std::size_t k = 0; k < theta.size(); ++k) {
    const double i1 = result.i1[k], i2 = result.i2[k];
    if (a.csv)
      fmt::print("{},{:.10e},{:.10e},{:.10e}", angles[k], i1, i2, (i1 + i2) / 2);
    else
      fmt::print("{:>10.4f}  {:>16.9e}  {:>16.9e}  {:>16.9e}", angles[k], i1, i2, (i1 + i2) / 2);
    if (mm && a.csv)
      fmt::print(",{:.10e},{:.10e},{:.10e},{:.10e}", mm->s11[k], mm->s12[k], mm->s33[k], mm->s34[k]);
    else if (mm)
      fmt::print("  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", mm->s11[k], mm->s12[k], mm->s33[k], mm->s34[k]);
    fmt::print("\n");
  }
  return 0;
}
}  // namespace

Command add_phase(CLI::App& app) {
  auto args = std::make_shared<PhaseArgs>();
  auto* sub = app.add_subcommand(
      "phase",
      "Scattered intensity against scattering angle for one drop: i1 = |S1|^2, i2 = |S2|^2 and "
      "their average, by Lorenz-Mie, one Debye order, Airy theory or geometric optics.");
  Command cmd{sub,
              [args] { return run_phase(*args); },
              {{"x", "--radius-um (size parameter x)"},
               {"m_real", "--medium/--surrounding (relative index, real part)"},
               {"m_imag", "--medium/--surrounding (relative index, imaginary part)"},
               {"r_max_m", "--radius-um (largest radius of the distribution, m)"},
               {"r_min_m", "--radius-um (smallest radius of the distribution, m)"},
               {"radius_um", "--radius-um"},
               {"wavelength_nm", "--wavelength-nm"},
               {"temperature_c", "--temperature-c"},
               {"p", "--theory (order P)"}}};
  // The declared parameters (nodes; temperature_c; threads; mueller) among this command's own.
  const auto params = scatter::phase_params();
  const auto declared = [&](std::size_t from) {
    add_params(*sub, args->r, params.subspan(from, 1), cmd.flags_for_quantity);
  };
  sub->add_option("--theory", args->theory,
                  "mie, debye:P (Debye order P: 0 diffraction + reflection, 2 primary rainbow, 3 "
                  "secondary), airy (primary rainbow; airy:P for order P), geometric (rays of orders "
                  "0-3 with interference; geometric:P for orders 0..P)")
      ->capture_default_str();
  sub->add_option("--radius-um", args->radius_um,
                  "Drop radius (the mean radius with gamma or lognormal), micrometres")
      ->check(positive_number(1e6, "um"));
  sub->add_option("--size-distribution", args->distribution,
                  "mono, gamma:W or lognormal:W (relative width W in [0.0001, 1] around --radius-um), or "
                  "marshall-palmer:H (rain of H in [0.01, 1000] mm/h, radii 50-3000 um)")
      ->capture_default_str();
  declared(0);  // --nodes
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->required()
      ->check(positive_number(1e6, "nm"));
  sub->add_option("--medium", args->medium, "Drop medium (see hydrolux ior --list)")->capture_default_str();
  sub->add_option("--surrounding", args->surrounding, "Surrounding medium")->capture_default_str();
  declared(1);  // --temperature-c
  sub->add_option("--angles-deg", args->angles,
                  "Scattering angles, degrees (0 = forward): A:B:N or a list 0,10,90")
      ->capture_default_str();
  declared(2);  // --threads
  sub->add_flag("--csv", args->csv,
                "Comma-separated output with a header row: theta_deg,i1,i2,i[,s11,s12,s33,s34 with --mueller]");
  declared(3);  // --mueller
  sub->add_flag("-q,--quiet", args->quiet, "No progress on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
