// hydrolux mie: Lorenz-Mie scattering by one sphere.
#include <fmt/format.h>

#include <chrono>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/sphere.hpp"

namespace hydrolux::cli {

namespace {
struct MieArgs {
  std::string m_text;
  std::optional<double> x;
  std::optional<double> radius_um, wavelength_nm, temperature_c;
  std::string medium = "water", surrounding = "air";
  std::string angles = "0:180:181";
  std::optional<int> debye;
  int threads = 0;
  bool json = false;
};

int run_mie(const MieArgs& a) {
  const bool dimensionless = !a.m_text.empty() || a.x;
  const bool physical = a.radius_um || a.wavelength_nm;
  if (dimensionless && physical)
    throw Error("give either --m and --x, or --radius-um and --wavelength-nm (with --medium), not both");
  scatter::Complex m;
  double x = 0;
  if (physical) {

    if (!a.radius_um || !a.wavelength_nm) throw Error("--radius-um and --wavelength-nm go together");
    const auto sphere = medium_flag("--medium", a.medium);
    const auto outside = medium_flag("--surrounding", a.surrounding);
    check_temperature_flag(a.temperature_c, {sphere.get(), outside.get()});
    const auto p = scatter::sphere_problem(*a.radius_um, *a.wavelength_nm, *sphere, *outside, a.temperature_c);
    m = p.m;
    x = p.x;
  } else {
    if (a.m_text.empty() || !a.x) throw Error("--m and --x go together (or use --radius-um and --wavelength-nm)");
    m = parse_complex(a.m_text, "--m");
    x = *a.x;
  }
  const auto angles = parse_angles_deg(a.angles, "--angles-deg");
  std::vector<double> mu(angles.size());
  for (std::size_t i = 0; i < mu.size(); ++i) mu[i] = std::cos(deg_to_rad(angles[i]));

  const auto start = std::chrono::steady_clock::now();
  scatter::MieCoefficients c;
  try {
    c = scatter::mie_coefficients(m, x);
  } catch (const DomainError& e) {
    if (!physical) throw;
    // In the physical form the solver's limits on x and m come from the drop and the light.
    const std::string flags = e.quantity() == "x" ? "--radius-um/--wavelength-nm (size parameter x)"
                                                  : "--medium/--surrounding (relative index m)";
    throw Error(fmt::format("{}: {} = {:g} is {}", flags, e.quantity(), e.value(), e.range_text()));
  }
  const auto q = scatter::mie_efficiencies(c);  // of the whole sphere, also with --debye
  std::vector<scatter::Complex> s1(mu.size()), s2(mu.size());
  scatter::mie_amplitudes(a.debye ? scatter::debye_coefficients(m, x, *a.debye) : c, mu, s1, s2, a.threads);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (a.json) {
    nlohmann::ordered_json j;
    j["x"] = x;
    j["m"] = {m.real(), m.imag()};
    j["n_terms"] = c.terms();
    j["qext"] = q.qext;
    j["qsca"] = q.qsca;
    j["qabs"] = q.qabs;
    j["qback"] = q.qback;
    j["g"] = q.g;
    if (a.debye) j["debye_p"] = *a.debye;
    j["angles_deg"] = angles;
    auto& j1 = j["s1"] = nlohmann::ordered_json::array();
    auto& j2 = j["s2"] = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < mu.size(); ++i) {
      j1.push_back({s1[i].real(), s1[i].imag()});
      j2.push_back({s2[i].real(), s2[i].imag()});
    }
    j["compute_s"] = seconds;
    std::cout << j.dump() << "\n";
    return 0;
  }
  fmt::print("x = {:.10g}, m = {:.8g}{:+.4g}i, {} terms (Wiscombe), computed in {:.3g} s\n", x, m.real(),
             m.imag(), c.terms(), seconds);
  fmt::print("Qext = {:.10g}  Qsca = {:.10g}  Qabs = {:.6g}  Qback = {:.8g}  g = {:.10g}\n", q.qext, q.qsca,
             q.qabs, q.qback, q.g);
  if (a.debye) fmt::print("amplitudes of Debye order p = {} alone\n", *a.debye);
  fmt::print("{:>10}  {:>16}  {:>16}  {:>16}  {:>16}\n", "theta_deg", "Re S1", "Im S1", "Re S2", "Im S2");
  for (std::size_t i = 0; i < mu.size(); ++i)
    fmt::print("{:>10.4f}  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}\n", angles[i], s1[i].real(), s1[i].imag(),
               s2[i].real(), s2[i].imag());
  return 0;
}
}  // namespace

Command add_mie(CLI::App& app) {
  auto args = std::make_shared<MieArgs>();
  auto* sub = app.add_subcommand(
      "mie",
      "Lorenz-Mie scattering by a homogeneous sphere: efficiencies and the amplitudes S1, S2 "
      "(Bohren & Huffman conventions). Give --m and --x, or the physical form --radius-um, "
      "--wavelength-nm, --medium.");
  auto* m_opt = sub->add_option("--m", args->m_text,
                                 "Relative complex index n+ki (k >= 0 absorbing), e.g. 1.333+1e-8i");
  auto* x_opt = sub->add_option("--x", args->x, "Size parameter 2 pi r / lambda")->check(number_in(1e-3, 1e5));
  sub->add_option("--radius-um", args->radius_um, "Sphere radius, micrometres")
      ->check(positive_number(1e6, "um"));
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->check(positive_number(1e6, "nm"));
  auto* medium_opt =
      sub->add_option("--medium", args->medium, "Sphere medium (see hydrolux ior --list)")->capture_default_str();
  auto* surrounding_opt =
      sub->add_option("--surrounding", args->surrounding, "Surrounding medium (air, or const:1 for vacuum)")
          ->capture_default_str();
  auto* temperature_opt =
      sub->add_option("--temperature-c", args->temperature_c, "Temperature in Celsius of the media that model it (water: 0 to 100); refused when neither "
                        "medium does")
          ->check(number_in(-273.15, 1000, "C"));
  // The dimensionless form takes m and x as they are: media flags would be silently ignored.
  for (auto* o : {m_opt, x_opt}) o->excludes(medium_opt)->excludes(surrounding_opt)->excludes(temperature_opt);
  sub->add_option("--angles-deg", args->angles,
                  "Scattering angles, degrees (0 = forward): A:B:N for N angles from A to B, or a list 0,10,90")
      ->capture_default_str();
  sub->add_option("--debye", args->debye,
                  "Restrict S1, S2 to Debye order P (0 diffraction + external reflection, 1 direct "
                  "transmission, 2 primary rainbow, 3 secondary, ...); efficiencies stay the whole sphere's")
      ->transform(integer_in(0, 1000));
  sub->add_option("--threads", args->threads, "Worker threads (0 = all cores)")
      ->transform(integer_in(0, 1024))
      ->capture_default_str();
  sub->add_flag("--json", args->json,
                "Print one JSON object: x, m, n_terms, qext, qsca, qabs, qback, g, [debye_p,] angles_deg, "
                "s1, s2 ([re, im] pairs), compute_s (seconds of computation alone)");
  return {sub,
          [args] { return run_mie(*args); },
          {{"x", "--x"},
           {"m_real", "--m (real part)"},
           {"m_imag", "--m (imaginary part)"},
           {"radius_um", "--radius-um"},
           {"wavelength_nm", "--wavelength-nm"},
           {"temperature_c", "--temperature-c"}}};
}

}  // namespace hydrolux::cli
