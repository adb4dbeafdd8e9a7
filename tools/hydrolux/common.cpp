#include "common.hpp"

#include <fmt/format.h>

#include <system_error>

#include <charconv>

#include <cmath>
#include <cstdio>
#include <mutex>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/optics/media.hpp"
#include "image_plugin.hpp"

namespace hydrolux::cli {

namespace {

std::string with_unit(const std::string& text, const std::string& unit) {
  return unit.empty() ? text : text + " " + unit;
}

CLI::Validator bounded(double lo, double hi, bool lo_open, const std::string& unit) {
  const std::string range = with_unit(fmt::format("{}{:g}, {:g}]", lo_open ? "(" : "[", lo, hi), unit);
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        const auto v = parse::number(s);
        if (!v) {
          // "1e-400" and "1e400" are numbers, just not ones a double holds.
          double probe = 0;
          const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), probe);
          const bool out_of_range = ec == std::errc::result_out_of_range && ptr == s.data() + s.size();
          return fmt::format("'{}' is {}; valid range {}", s,
                             out_of_range ? "beyond what a double holds (about 1e-308 to 1e308 in magnitude)"
                                          : "not a finite number",
                             range);
        }
        if ((lo_open ? !(*v > lo) : !(*v >= lo)) || !(*v <= hi))
          return fmt::format("{} is outside the valid range {}", s, range);
        return {};
      },
      range);
}

// The name is read by the signal thread while the main thread may set it: guarded.
struct ProgramName {
  std::mutex mutex;
  std::string name = "hydrolux";
};
ProgramName& program_name_storage() {
  static ProgramName* p = new ProgramName;  // never destroyed: the signal thread may read it at exit
  return *p;
}

}  // namespace

CLI::Validator number_in(double lo, double hi, const std::string& unit) { return bounded(lo, hi, false, unit); }

CLI::Validator positive_number(double hi, const std::string& unit) { return bounded(0, hi, true, unit); }

CLI::Validator integer_in(long long lo, long long hi, const std::string& unit) {
  const std::string range = with_unit(fmt::format("[{}, {}]", lo, hi), unit);
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        const auto v = parse::integer(s);
        if (!v) {
          const auto x = parse::number(s);
          if (x && *x == std::floor(*x)) return fmt::format("{} is outside the valid range {}", s, range);
          if (x) return fmt::format("{} is not a whole number; valid range {}", s, range);
          return fmt::format("'{}' is not a whole number; valid range {}", s, range);
        }
        if (*v < lo || *v > hi) return fmt::format("{} is outside the valid range {}", s, range);
        s = std::to_string(*v);  // "1e3" -> "1000" for CLI11's integer conversion
        return {};
      },
      range);
}

std::complex<double> parse_complex(const std::string& text, const std::string& flag) {
  const auto v = parse::complex_number(text);
  if (!v) throw Error(fmt::format("{} '{}': expected a complex index like 1.333 or 1.333+1e-8i", flag, text));
  return *v;
}

std::vector<double> parse_angles_deg(const std::string& text, const std::string& flag) {
  try {
    return parse::range_or_list(text, 0, 180, 1000000);
  } catch (const Error& e) {
    throw Error(fmt::format("{} '{}': {}; expected A:B:N (N angles from A to B, N in [2, 1000000], or 1 with A == "
                            "B) or a strictly increasing or decreasing list 0,10,90, angles in [0, 180] deg",
                            flag, text, e.what()));
  }
}

std::shared_ptr<const optics::Medium> medium_flag(const std::string& flag, const std::string& name) {
  try {
    return optics::find_medium(name);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("{}: {}", flag, e.what()));
  } catch (const DomainError& e) {  // const:<n> with n outside its range
    throw Error(fmt::format("{} {}: {} {:g} is {}", flag, name, e.quantity(), e.value(), e.range_text()));
  }
}

void check_temperature_flag(const std::optional<double>& temperature_c, const std::vector<const optics::Medium*>& media) {
  if (!temperature_c) return;
  bool used = false;
  for (const auto* m : media) {
    const auto& info = m->info();
    if (!info.temperature_dependent) continue;
    used = true;
    if (!(*temperature_c >= info.temperature_min_c && *temperature_c <= info.temperature_max_c))
      throw Error(fmt::format("--temperature-c {:g} is outside the valid range [{:g}, {:g}] C of {}", *temperature_c,
                              info.temperature_min_c, info.temperature_max_c, info.name));
  }
  if (used) return;
  std::string names, models;
  for (const auto* m : media) names += (names.empty() ? "" : " and ") + m->info().name;
  for (const auto& name : optics::medium_names())
    if (optics::find_medium(name)->info().temperature_dependent) models += (models.empty() ? "" : ", ") + name;
  throw Error(fmt::format("--temperature-c {:g}: {} {} no temperature model (only {} {}); omit the flag",
                          *temperature_c, names, media.size() > 1 ? "have" : "has", models,
                          models.find(',') == std::string::npos ? "uses it" : "use it"));
}

void set_program_name(std::string name) {
  auto& p = program_name_storage();
  std::lock_guard lock(p.mutex);
  p.name = printable(name);  // argv words may hold anything
}
std::string program_name() {
  auto& p = program_name_storage();
  std::lock_guard lock(p.mutex);
  return p.name;
}

namespace {
std::string& command_line_storage() {
  static std::string line = "hydrolux";
  return line;
}
}  // namespace

void set_command_line(int argc, const char* const* argv) {
  std::string line = "hydrolux";
  for (int i = 1; i < argc; ++i) {
    const std::string word = printable(argv[i]);
    const bool plain = !word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                                               "0123456789_-+=.,:/@%") == std::string::npos;
    line += ' ';
    if (plain) {
      line += word;
    } else {
      line += '\'';
      for (char c : word) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
      line += '\'';
    }
  }
  command_line_storage() = std::move(line);
}
std::string command_line() { return command_line_storage(); }

void warn(const std::string& text) {
  // A warning that cannot be written (a full disk under stderr) is dropped: the job goes on to its own
  // outcome, which the exit code reports.
  try {
    fmt::print(stderr, "{}: warning: {}\n", program_name(), printable(text));
  } catch (const std::system_error&) {
  }
}

int report_left_out(const std::vector<std::string>& left_out, std::size_t frames_total) {
  if (left_out.empty()) return 0;
  std::string list;
  for (const auto& f : left_out) list += (list.empty() ? "" : ", ") + f;
  fmt::print(stderr, "{}: {} of {} frames left out ({}); the others are written\n", program_name(), left_out.size(),
             frames_total, printable(list));
  return kExitFailure;
}

ImageOutput declare_output_image(io::FileSet& files, const std::string& flag, const std::string& path) {
  const io::ImageFormat format = io::output_image_format(path, flag);
  return {&files.output(flag, path), format};
}

io::DecodedImage read_input_decoded(const std::string& flag, const std::string& path) {
  (void)image_api();  // loaded before reading: a missing plugin is reported first
  return io::read_decoded(image_codec(), flag, path, [](const std::string& w) { warn(w); });
}

Image read_input_image(const std::string& flag, const std::string& path) {
  return std::move(read_input_decoded(flag, path).image);
}

void write_output_image(const ImageOutput& out, const Image& image) {
  out.file->write(image_api().encode_image(image, out.format, io::PngOptions{}));
}

std::optional<std::array<int, 2>> parse_size(const std::string& text) {
  const auto p = parse::pair(text, 'x');
  if (!p) return std::nullopt;
  for (double v : *p)
    if (v != std::floor(v) || v < 1 || v > 16384) return std::nullopt;
  return std::array<int, 2>{int((*p)[0]), int((*p)[1])};
}

CLI::Validator size_validator() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        if (!parse_size(s)) return fmt::format("'{}' is not WxH (whole numbers in [1, 16384], e.g. 640x480)", s);
        return {};
      },
      "WxH");
}

}  // namespace hydrolux::cli
