// hydrolux drop ...: Garg & Nayar's rain drop model.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "hydrolux/drop/model.hpp"
#include "hydrolux/drop/physics_params.hpp"
#include "params.hpp"

namespace hydrolux::cli {

namespace {
// The numbers are drop/physics_params.hpp's; the output's form is this command's.
struct ProfileArgs {
  std::shared_ptr<drop::DropProfileRequest> r = std::make_shared<drop::DropProfileRequest>();
  bool json = false;
};

int run_profile(const ProfileArgs& args) {
  const drop::DropProfileRequest& a = *args.r;
  const auto f = drop::radiance_profile(a.mu, a.samples, 2);
  if (args.json) {
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
  auto* sub = add_job_command(drop, "drop_profile");
  Command cmd{sub, [args] { return run_profile(*args); }, {}};
  add_params(*sub, args->r, drop::drop_profile_params(), cmd.flags_for_quantity);
  sub->add_flag("--json", args->json,
                "Print one JSON object: rho, refraction, reflection, internal1, internal2 (arrays), fov_deg");
  return cmd;
}

}  // namespace hydrolux::cli
