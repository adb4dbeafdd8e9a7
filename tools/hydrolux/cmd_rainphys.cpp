// hydrolux rainphys: the physical properties of a rain drop that Garg & Nayar (2004, section 2)
// build on: terminal velocity, the Marshall-Palmer size distribution, the equilibrium shape.
#include <fmt/format.h>

#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/drop/physics.hpp"
#include "hydrolux/drop/physics_params.hpp"
#include "hydrolux/scatter/drop_shape.hpp"
#include "hydrolux/scatter/size_distribution.hpp"
#include "params.hpp"

namespace hydrolux::cli {

namespace {
// The numbers are drop/physics_params.hpp's; the output's form is this command's.
struct RainphysArgs {
  std::shared_ptr<drop::RainphysRequest> r = std::make_shared<drop::RainphysRequest>();
  bool json = false;
};

// Radii over which the paper's fit v = 200 sqrt(a) stays within 11% of Gunn & Kinzer's
// measurements (drop/physics.hpp; pinned in tests/drop/test_physics.cpp).
constexpr double kFitValidMaxRadiusMm = 2.5;

int run_rainphys(const RainphysArgs& args) {
  const drop::RainphysRequest& a = *args.r;
  const double radius_m = a.radius_mm / 1e3;
  std::vector<std::string> notes;

  const double v_fit = drop::terminal_velocity_fit_mps(radius_m);
  if (a.radius_mm > kFitValidMaxRadiusMm)
    notes.push_back(fmt::format("terminal_velocity_mps: the fit v = 200 sqrt(a) holds within 11% of Gunn & "
                                "Kinzer's measurements for radii 0.5-2.5 mm; above that it overestimates "
                                "(by 17% at 2.9 mm) as the velocity of large drops saturates near 9.2 m/s"));
  std::optional<double> v_gk;
  const auto gk_range = drop::gunn_kinzer_radius_range_m();
  if (radius_m >= gk_range[0] && radius_m <= gk_range[1]) {
    v_gk = drop::terminal_velocity_gunn_kinzer_mps(radius_m);
  } else {
    notes.push_back(fmt::format("terminal_velocity_gunn_kinzer_mps: not available, Gunn & Kinzer (1949) "
                                "measured drops of radius {:g}-{:g} mm only",
                                gk_range[0] * 1e3, gk_range[1] * 1e3));
  }

  const auto mp = scatter::SizeDistribution::marshall_palmer(a.rain_rate_mmh);
  const double density = mp.number_density(radius_m);
  const double number = mp.number_concentration();
  const double spacing = std::cbrt(1.0 / number);

  scatter::DropShape shape;
  try {
    shape = scatter::drop_shape(radius_m);
  } catch (const DomainError& e) {  // the validator's range is the table's; kept for safety
    throw Error(fmt::format("--radius-mm {:g} is outside the valid range [{:g}, {:g}] mm of {}", a.radius_mm,
                            e.lo() * 1e3, e.hi() * 1e3, e.context()));
  }
  const std::vector<double> c1_10(shape.c.begin() + 1, shape.c.end());
  const double ratio = scatter::axis_ratio(shape);
  const double height_mm = scatter::vertical_extent_m(shape) * 1e3;
  const double width_mm = scatter::horizontal_extent_m(shape) * 1e3;

  if (args.json) {
    nlohmann::ordered_json j;
    j["terminal_velocity_mps"] = v_fit;
    j["terminal_velocity_gunn_kinzer_mps"] = v_gk ? nlohmann::ordered_json(*v_gk) : nlohmann::ordered_json(nullptr);
    j["density_per_m4"] = density;
    j["shape_coefficients"] = c1_10;
    j["axis_ratio"] = ratio;
    j["c0"] = shape.c[0];
    j["radius_mm"] = a.radius_mm;
    j["rain_rate_mmh"] = a.rain_rate_mmh;
    j["number_density_per_m3"] = number;
    j["mean_spacing_m"] = spacing;
    j["lambda_per_m"] = mp.lambda();
    j["height_mm"] = height_mm;
    j["width_mm"] = width_mm;
    j["notes"] = notes;
    std::cout << j.dump() << "\n";
    return 0;
  }

  const auto line = [](const char* label, const std::string& value) { fmt::print("{:<34}{}\n", label, value); };
  fmt::print("# rain drop of equivalent radius {:g} mm in rain of {:g} mm/h (Garg & Nayar 2004, section 2)\n",
             a.radius_mm, a.rain_rate_mmh);
  line("terminal velocity, fit", fmt::format("{:.4f} m/s   (v = 200 sqrt(a))", v_fit));
  line("terminal velocity, Gunn & Kinzer", v_gk ? fmt::format("{:.4f} m/s   (measured, 1949)", *v_gk)
                                                 : std::string("-            (outside their measurements)"));
  line("size density N(a)", fmt::format("{:.6g} m^-4   (drops per m^3 per m of radius)", density));
  line("number density (all drops)", fmt::format("{:.6g} m^-3   (N0 / Lambda)", number));
  line("mean spacing", fmt::format("{:.4g} m   (n^(-1/3))", spacing));
  line("Lambda", fmt::format("{:.6g} m^-1   (8200 h^-0.21)", mp.lambda()));
  line("axis ratio", fmt::format("{:.4f}   (height / width)", ratio));
  line("height x width", fmt::format("{:.4f} mm x {:.4f} mm", height_mm, width_mm));
  std::string coeffs;
  for (std::size_t n = 0; n < shape.c.size(); ++n) coeffs += fmt::format("{}{:.5f}", n ? " " : "", shape.c[n]);
  line("shape c0..c10", coeffs);
  line("", "(r = a (1 + sum c_n cos(n theta)), theta = 0 along the fall)");
  for (const auto& n : notes) fmt::print("note: {}\n", n);
  return 0;
}
}  // namespace

Command add_rainphys(CLI::App& app) {
  auto args = std::make_shared<RainphysArgs>();
  auto* sub = add_job_command(app, "rainphys");
  Command cmd{sub, [args] { return run_rainphys(*args); }, {}};
  add_params(*sub, args->r, drop::rainphys_params(), cmd.flags_for_quantity);
  sub->add_flag("--json", args->json,
                "Print one JSON object: terminal_velocity_mps, terminal_velocity_gunn_kinzer_mps (null outside "
                "Gunn & Kinzer's radii, 0.039-2.9 mm), density_per_m4, shape_coefficients ([c1..c10]), "
                "axis_ratio, c0, radius_mm, rain_rate_mmh, number_density_per_m3, mean_spacing_m, "
                "lambda_per_m, height_mm, width_mm, notes (array of strings)");
  return cmd;
}

}  // namespace hydrolux::cli
