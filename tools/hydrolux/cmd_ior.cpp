// hydrolux ior: refractive index of a built-in medium.
#include <fmt/format.h>

#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/params.hpp"
#include "hydrolux/optics/media.hpp"
#include "hydrolux/optics/params.hpp"
#include "params.hpp"

namespace hydrolux::cli {

namespace {
struct IorArgs {
  std::string medium;
  double wavelength_nm = 0;
  std::shared_ptr<optics::IorRequest> r = std::make_shared<optics::IorRequest>();  // the declared numbers
  bool json = false;
  bool list = false;
};

std::string temperature_text(const optics::MediumInfo& i) {
  if (i.temperature_dependent)
    return fmt::format("{:g} to {:g} C (default {:g})", i.temperature_min_c, i.temperature_max_c,
                       i.default_temperature_c);
  return fmt::format("data at {:g} C", i.default_temperature_c);
}

int list_media(bool json) {
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  for (const auto& name : optics::medium_names()) {
    const auto& i = optics::find_medium(name)->info();
    if (json) {
      all.push_back({{"medium", i.name},
                     {"description", i.description},
                     {"source", i.source},
                     {"wavelength_nm", {i.lambda_min_nm, i.lambda_max_nm}},
                     {"temperature_c", {i.temperature_min_c, i.temperature_max_c}},
                     {"temperature_dependent", i.temperature_dependent},
                     {"conductor", i.conductor}});
    } else {
      fmt::print("{:<13} {:>6g}-{:<6g} nm  {:<28}  {}\n", i.name, i.lambda_min_nm, i.lambda_max_nm,
                 temperature_text(i), i.description);
    }
  }
  if (json)
    std::cout << all.dump() << "\n";
  else
    fmt::print("const:<n>[+<k>i]  any wavelength  a constant index, e.g. const:1.49\n");
  return 0;
}

int run_ior(const IorArgs& a) {
  if (a.list) return list_media(a.json);
  if (a.medium.empty()) throw Error("--medium is required (hydrolux ior --list shows the media)");
  if (a.wavelength_nm == 0) throw Error("--wavelength-nm is required");
  std::shared_ptr<const optics::Medium> medium;
  try {
    medium = optics::find_medium(a.medium);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("--medium: {}", e.what()));
  }
  const auto& info = medium->info();
  if (a.r->temperature_c && !info.temperature_dependent &&
      *a.r->temperature_c != info.default_temperature_c)
    throw Error(fmt::format(
        "--temperature-c {:g}: {} has no temperature model (its data are at {:g} C); omit the flag",
        *a.r->temperature_c, info.name, info.default_temperature_c));
  const auto idx = medium->index(a.wavelength_nm, a.r->temperature_c);
  if (a.json) {
    nlohmann::ordered_json j = {{"medium", info.name},
                        {"wavelength_nm", a.wavelength_nm},
                        {"n", idx.real()},
                        {"k", idx.imag()}};
    if (info.temperature_dependent)
      j["temperature_c"] = a.r->temperature_c.value_or(info.default_temperature_c);
    std::cout << j.dump() << "\n";
    return 0;
  }
  fmt::print("{} at {:g} nm", info.name, a.wavelength_nm);
  if (info.temperature_dependent)
    fmt::print(", {:g} C", a.r->temperature_c.value_or(info.default_temperature_c));
  fmt::print(": n = {:.8g}, k = {:.6g}\n", idx.real(), idx.imag());
  fmt::print("source: {}\n", info.source);
  return 0;
}
}  // namespace

Command add_ior(CLI::App& app) {
  auto args = std::make_shared<IorArgs>();
  auto* sub = add_job_command(app, "ior");
  sub->add_option("--medium", args->medium,
                  "Medium name (see --list), or const:<n>[+<k>i] for a constant index");
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->check(positive_number(1e6, "nm"));
  Command cmd{sub, [args] { return run_ior(*args); }, {{"wavelength_nm", "--wavelength-nm"}}};
  add_params(*sub, args->r, optics::ior_params(), cmd.flags_for_quantity);
  sub->add_flag("--json", args->json,
                "Print one JSON object: medium, wavelength_nm, n, k (and temperature_c for water)");
  sub->add_flag("--list", args->list, "List the media with their valid ranges and sources");
  return cmd;
}

}  // namespace hydrolux::cli
