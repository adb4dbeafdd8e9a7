#pragma once
// Shared pieces of the hydrolux CLI: how subcommands register, the validators that give the
// one-line "flag, value, valid range" errors, the media and temperature flags, and image files
// read and written through the library's one safe path (io/files.hpp).
#include <CLI/CLI.hpp>

#include <array>
#include <complex>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hydrolux/core/image.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/image_io.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::cli {

inline constexpr int kExitUsage = 2;     // bad input: a flag, a value or a file; nothing written
inline constexpr int kExitFailure = 1;   // the system failed midway (full disk), or a bug

// A subcommand's action, run after parsing. Returns the exit code.
using Action = std::function<int()>;

// Each subcommand adds itself to `app` and returns its action.
struct Command {
  CLI::App* app;
  Action run;
  // Library DomainError quantities ("wavelength_nm") -> the flag that set them ("--wavelength-nm").
  std::map<std::string, std::string> flags_for_quantity;
  // A quantity or parameter a library message names ({near_m}) as this command's flag: its entry in
  // flags_for_quantity, else the flag of that name ("--near-m").
  std::string flag(std::string_view quantity) const;
};

// Every subcommand, registered on `app` (main.cpp; tests walk the same tree).
std::vector<Command> add_all_commands(CLI::App& app);
// docs/reference.md for `commands`: a table of flags per command (reference.cpp).
std::string reference_markdown(const std::vector<Command>& commands);
// Runs the CLI: parse, dispatch, errors to exit codes. Installs the signal handling first.
int run_cli(int argc, char** argv);

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
Command add_lee(CLI::App& app);
Command add_sky(CLI::App& app);
Command add_export(CLI::App& app);
Command add_rain(CLI::App& app);
Command add_fog(CLI::App& app);
Command add_lens_drops(CLI::App& app);
Command add_detect_rain(CLI::App& app);
Command add_remove_rain(CLI::App& app);
Command add_rain_eval(CLI::App& app);
Command add_medium(CLI::App& app);
Command add_spec(CLI::App& app);

// ---- validators: each gives "'<value>' ... valid range [lo, hi] <unit>" ----

// A finite number in [lo, hi]. Rejects NaN, inf and non-numeric text.
CLI::Validator number_in(double lo, double hi, const std::string& unit = {});
// A finite number > 0 (at most `hi`).
CLI::Validator positive_number(double hi, const std::string& unit = {});
// A whole number in [lo, hi]. Attach it with ->transform(), not ->check(): "1e3" is accepted and
// rewritten to "1000" for CLI11's integer conversion, which only a transform may do.
CLI::Validator integer_in(long long lo, long long hi, const std::string& unit = {});

// An image or table size "WxH": whole numbers in [1, 16384]; nullopt otherwise. The validator
// gives the one-line error for a --size flag.
std::optional<std::array<int, 2>> parse_size(const std::string& text);
CLI::Validator size_validator();

// ---- text forms, naming the flag in their errors (hydrolux::Error) ----

// "1.333", "1.333+1e-8i": a complex number.
std::complex<double> parse_complex(const std::string& text, const std::string& flag);
// Scattering angles in degrees: "A:B:N" or "0,10,90"; each in [0, 180], N in [2, 1e6] (1 with A ==
// B), strictly increasing or decreasing (parse::range_or_list).
std::vector<double> parse_angles_deg(const std::string& text, const std::string& flag);

// ---- media ----

// The medium named on `flag`; an unknown name is an error naming the flag and the valid names.
std::shared_ptr<const optics::Medium> medium_flag(const std::string& flag, const std::string& name);
// A --temperature-c given for `media`: at least one of them must model temperature (the error
// names those that do), and the value must lie in each such medium's range.
void check_temperature_flag(const std::optional<double>& temperature_c,
                            const std::vector<const optics::Medium*>& media);

// ---- files ----

// The name of the running command ("hydrolux drop render"), for warnings.
void set_program_name(std::string name);
std::string program_name();  // thread-safe: the signal thread reads it
// The command line as run ("hydrolux lee --table corona -o t.nc", words quoted for a POSIX shell where
// they need it), for the `history` attribute of the files that carry one (NetCDF).
void set_command_line(int argc, const char* const* argv);
std::string command_line();
// One line on stderr: "<program>: warning: <text>".
void warn(const std::string& text);
// A folder run's frames left out (rain, fog, lens-drops): none, 0; else one line naming them on
// stderr ("N of M frames left out (...); the others are written") and kExitFailure.
int report_left_out(const std::vector<std::string>& left_out, std::size_t frames_total);

// An image output declared in a FileSet: where it goes and in which format.
struct ImageOutput {
  io::OutputFile* file;
  io::ImageFormat format;
};
// Declares an image output in `files`: the extension must be .png or .exr; the output is reserved
// (its folder exists and takes a file; it is not an input).
ImageOutput declare_output_image(io::FileSet& files, const std::string& flag, const std::string& path);
// Reads an image declared as an input: the bytes through the library's checked reader, decoded by
// the image plugin; the codec's warnings become one warning line each.
Image read_input_image(const std::string& flag, const std::string& path);
// The same with the format the content was decoded as (for inputs that must be of one format).
io::DecodedImage read_input_decoded(const std::string& flag, const std::string& path);
// Encodes an image (the plugin's encoder) into a declared output; committed with the FileSet.
void write_output_image(const ImageOutput& out, const Image& image);

}  // namespace hydrolux::cli
