// hydrolux drop ...: Garg & Nayar's rain drop model.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "hydrolux/drop/model.hpp"

namespace hydrolux::cli {

namespace {
struct ProfileArgs {
  double mu = 1.333;
  int samples = 101;
  bool json = false;
};

int run_profile(const ProfileArgs& a) {
  const auto f = drop::radiance_profile(a.mu, a.samples, 2);
  if (a.json) {
    nlohmann::ordered_json j;
    j["rho"] = f.rho;
    j["refraction"] = f.refraction;
    j["reflection"] = f.reflection;
    j["internal1"] = f.internal[0];
    j["internal2"] = f.internal[1];
    j["fov_deg"] = f.fov_deg;
    std::cout << j.dump() << "\n";
    return 0;
  }
  fmt::print("# Garg & Nayar Figure 4: radiance of each path for Le = 1, alpha = 0, mu = {:g}; field of view "
             "{:.2f} deg\n",
             a.mu, f.fov_deg);
  fmt::print("{:>8}  {:>12}  {:>12}  {:>12}  {:>12}\n", "rho", "refraction", "reflection", "internal1", "internal2");
  for (std::size_t s = 0; s < f.rho.size(); ++s)
    fmt::print("{:>8.4f}  {:>12.6e}  {:>12.6e}  {:>12.6e}  {:>12.6e}\n", f.rho[s], f.refraction[s], f.reflection[s],
               f.internal[0][s], f.internal[1][s]);
  return 0;
}
}  // namespace

std::vector<Command> add_drop(CLI::App& app) {
  auto* drop = app.add_subcommand("drop", "Garg & Nayar's rain drop model: profile, render, undistort");
  drop->require_subcommand(1);
  return {add_drop_profile(*drop), add_drop_render(*drop), add_drop_undistort(*drop)};
}

Command add_drop_profile(CLI::App& drop) {
  auto args = std::make_shared<ProfileArgs>();
  auto* sub = drop.add_subcommand(
      "profile",
      "Figure 4 of Garg & Nayar: the radiance of the refracted, reflected and internally reflected "
      "paths across the drop's image (rho = 0 centre to 1 rim) for a uniform environment Le = 1, "
      "drop on the optical axis; and the drop's field of view.");
  sub->add_option("--mu", args->mu, "Refractive index of the drop relative to the air")
      ->check(number_in(1.0001, 10))
      ->capture_default_str();
  sub->add_option("--samples", args->samples, "Number of rho values from 0 to 1")
      ->transform(integer_in(2, 1000000))
      ->capture_default_str();
  sub->add_flag("--json", args->json,
                "Print one JSON object: rho, refraction, reflection, internal1, internal2 (arrays), fov_deg");
  return {sub, [args] { return run_profile(*args); }, {{"mu", "--mu"}, {"samples", "--samples"}}};
}

}  // namespace hydrolux::cli
