// hydrolux command-line tool: parses arguments, calls the library, prints or writes results.
// Exit codes: 0 success, 2 bad input (one line on stderr naming the flag, value and valid range),
// 1 unexpected internal failure.
#include <fmt/format.h>

#include <cstdio>
#include <iostream>
#include <vector>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/version.hpp"

int main(int argc, char** argv) {
  using namespace hydrolux;
  CLI::App app{"hydrolux: physically based light transport through water drops.\n"
               "Units: angles in degrees, wavelengths in vacuum nanometres, temperatures in Celsius.",
               "hydrolux"};
  app.set_version_flag("--version", fmt::format("hydrolux {}", kVersion));
  app.require_subcommand(1);
  app.allow_extras(false);
  app.get_formatter()->column_width(34);

  std::vector<cli::Command> commands = {cli::add_fresnel(app), cli::add_ior(app), cli::add_mie(app),
                                        cli::add_phase(app)};
  for (auto& c : cli::add_drop(app)) commands.push_back(std::move(c));
  commands.push_back(cli::add_rainphys(app));
  commands.push_back(cli::add_gallery(app));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string msg = e.what();
    if (msg.empty()) msg = "invalid arguments";
    fmt::print(stderr, "hydrolux: {} (see hydrolux --help)\n", msg);
    return cli::kExitUsage;
  }

  for (const auto& cmd : commands) {
    if (!cmd.app->parsed()) continue;
    std::string prog = cmd.app->get_name();
    for (auto* p = cmd.app->get_parent(); p && p != &app; p = p->get_parent()) prog = p->get_name() + " " + prog;
    prog = "hydrolux " + prog;
    try {
      const int code = cmd.run();
      std::cout.flush();
      if (std::fflush(stdout) != 0 || std::ferror(stdout) || std::cout.fail()) {
        fmt::print(stderr, "{}: cannot write to standard output\n", prog);
        return cli::kExitInternal;
      }
      return code;
    } catch (const DomainError& e) {
      const auto it = cmd.flags_for_quantity.find(e.quantity());
      if (it != cmd.flags_for_quantity.end())
        fmt::print(stderr, "{}: {} {:g} is {}\n", prog, it->second, e.value(), e.range_text());
      else
        fmt::print(stderr, "{}: {}\n", prog, e.what());
      return cli::kExitUsage;
    } catch (const Error& e) {
      fmt::print(stderr, "{}: {}\n", prog, e.what());
      return cli::kExitUsage;
    } catch (const std::exception& e) {
      fmt::print(stderr, "{}: internal error: {}\n", prog, e.what());
      return cli::kExitInternal;
    }
  }
  return cli::kExitInternal;  // unreachable: require_subcommand(1)
}
