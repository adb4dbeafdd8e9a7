// hydrolux fresnel: reflectance and transmittance of one plane interface.
#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/params.hpp"
#include "params.hpp"

namespace hydrolux::cli {

namespace {
// The numbers are optics/params.hpp's; the output's form is this command's.
struct FresnelArgs {
  std::shared_ptr<optics::FresnelRequest> r = std::make_shared<optics::FresnelRequest>();
  bool json = false;
};

int run_fresnel(const FresnelArgs& args) {
  const optics::FresnelRequest& a = *args.r;
  const double theta_deg = a.theta_deg.value();  // a required flag
  const double theta = deg_to_rad(theta_deg);
  const double cos_i = std::cos(theta);
  nlohmann::ordered_json j;
  if (a.k2 > 0) {  // absorbing medium: no propagating transmitted beam
    const auto f = optics::fresnel_conductor(cos_i, a.n1, std::complex<double>(a.n2, a.k2));
    j = {{"theta_t_deg", nullptr}, {"rs", f.R_s}, {"rp", f.R_p}, {"r", f.R},
         {"t", nullptr},           {"tir", false}};
  } else {
    const auto f = optics::fresnel_dielectric(cos_i, a.n1, a.n2);
    j = {{"theta_t_deg", f.tir ? nlohmann::ordered_json(nullptr)
                               : nlohmann::ordered_json(rad_to_deg(safe_acos(f.cos_t)))},
         {"rs", f.R_s}, {"rp", f.R_p}, {"r", f.R}, {"t", f.T}, {"tir", f.tir}};
  }
  if (args.json) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  const auto num = [](const nlohmann::ordered_json& v) {
    return v.is_null() ? std::string("-") : fmt::format("{:.8g}", v.get<double>());
  };
  fmt::print("interface   n1 = {:g} -> n2 = {:g}{}  at theta_i = {:g} deg\n", a.n1, a.n2,
             a.k2 > 0 ? fmt::format(" + {:g}i", a.k2) : "", theta_deg);
  fmt::print("theta_t     {} deg{}\n", num(j["theta_t_deg"]),
             j["tir"].get<bool>() ? " (total internal reflection)"
                                  : (a.k2 > 0 ? " (absorbing medium: no refracted beam)" : ""));
  fmt::print("R_s         {}\n", num(j["rs"]));
  fmt::print("R_p         {}\n", num(j["rp"]));
  fmt::print("R           {}   (unpolarised, (R_s + R_p) / 2)\n", num(j["r"]));
  fmt::print("T           {}{}\n", num(j["t"]), a.k2 > 0 ? "   (1 - R is absorbed)" : "");
  fmt::print("TIR         {}\n", j["tir"].get<bool>() ? "yes" : "no");
  return 0;
}
}  // namespace

Command add_fresnel(CLI::App& app) {
  auto args = std::make_shared<FresnelArgs>();
  auto* sub = add_job_command(app, "fresnel");
  Command cmd{sub, [args] { return run_fresnel(*args); }, {}};
  add_params(*sub, args->r, optics::fresnel_params(), cmd.flags_for_quantity);
  sub->get_option(std::string(optics::fresnel_params().back().param.flag))->required();
  sub->add_flag("--json", args->json,
                "Print one JSON object: theta_t_deg, rs, rp, r, t, tir (theta_t_deg and t are null "
                "for a conductor; theta_t_deg is null under total internal reflection)");
  return cmd;
}

}  // namespace hydrolux::cli
