#pragma once
// Shared pieces of the hydrolux CLI: how subcommands register, input validators that produce the
// one-line "flag, value, valid range" errors, and how library errors become exit code 2.
#include <CLI/CLI.hpp>

#include <complex>
#include <functional>
#include <vector>
#include <map>
#include <string>

namespace hydrolux::cli {

inline constexpr int kExitUsage = 2;     // bad input: flag, value or file
inline constexpr int kExitInternal = 1;  // a bug or an unexpected failure

// A subcommand's action, run after parsing. Returns the exit code.
using Action = std::function<int()>;

// Each subcommand adds itself to `app` and returns its action.
struct Command {
  CLI::App* app;
  Action run;
  // Library DomainError quantities ("wavelength_nm") -> the flag that set them ("--wavelength-nm").
  std::map<std::string, std::string> flags_for_quantity;
};

Command add_fresnel(CLI::App& app);
Command add_ior(CLI::App& app);
Command add_gallery(CLI::App& app);
Command add_mie(CLI::App& app);
Command add_phase(CLI::App& app);
// `hydrolux drop ...`: the drop subcommand and its own subcommands (profile, render, undistort).
std::vector<Command> add_drop(CLI::App& app);
Command add_drop_profile(CLI::App& drop);
Command add_drop_render(CLI::App& drop);
Command add_drop_undistort(CLI::App& drop);
Command add_rainphys(CLI::App& app);

// A finite number in [lo, hi] (unit printed in help and errors, e.g. "deg"). Rejects NaN, inf and
// non-numeric text with the valid range in the message.
CLI::Validator number_in(double lo, double hi, const std::string& unit = {});
// A finite number > 0 (at most `hi`).
CLI::Validator positive_number(double hi, const std::string& unit = {});

// "1.333", "1.333+1e-8i", "1.333-0i": a complex number; throws hydrolux::Error naming `flag`.
std::complex<double> parse_complex(const std::string& text, const std::string& flag);

// Scattering angles in degrees: "A:B:N" (N evenly spaced values from A to B inclusive) or a
// comma-separated list "0,10,90"; each in [0, 180], N in [1, 1e6]. Throws hydrolux::Error
// naming `flag`.
std::vector<double> parse_angles_deg(const std::string& text, const std::string& flag);

// Checks an output image path before any work is done: the extension must be .png or .exr (returned
// lower-case, with the dot) and the parent directory must exist. Throws hydrolux::Error naming `flag`.
std::string output_image_extension(const std::string& path, const std::string& flag);

}  // namespace hydrolux::cli
