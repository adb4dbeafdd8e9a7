// hydrolux mie: Lorenz-Mie scattering by one sphere.
#include <fmt/format.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "common.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/netcdf.hpp"
#include "hydrolux/io/npy.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/debye.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/mie_dataset.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/scatter/params.hpp"
#include "hydrolux/scatter/sphere.hpp"
#include "params.hpp"
#include "progress.hpp"

namespace hydrolux::cli {

namespace {
// The numbers and switches are scatter/params.hpp's; the index, the physical form's radius,
// wavelength and media, the angles and the output are this command's.
struct MieArgs {
  std::shared_ptr<scatter::MieRequest> r = std::make_shared<scatter::MieRequest>();
  std::string m_text;
  std::optional<double> radius_um, wavelength_nm;
  std::string medium = "water", surrounding = "air";
  std::string angles = "0:180:181";
  bool json = false, quiet = false;
  std::optional<std::string> output;
};

// Where a large output goes: stdout or a reserved output file, in pieces of about a megabyte, so
// that a million angles never sit in memory as text.
class Sink {
 public:
  explicit Sink(io::OutputFile* file) : file_(file) { buffer_.reserve(kChunk + 4096); }
  std::string& buffer() { return buffer_; }
  // Passes the buffer on once it holds a chunk (or always, with force).
  void flush(bool force = false) {
    if (buffer_.empty() || (!force && buffer_.size() < kChunk)) return;
    if (file_) {
      file_->write(buffer_);
    } else if (std::fwrite(buffer_.data(), 1, buffer_.size(), stdout) != buffer_.size()) {
      throw IoFailure(fmt::format("cannot write to standard output: {}", std::strerror(errno)));
    }
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kChunk = 1 << 20;
  io::OutputFile* file_;
  std::string buffer_;
};

// The JSON object's members after "angles_deg": the angle array and S1, S2 as [re, im] pairs,
// then the Mueller elements if given, streamed (numbers in their shortest round-trip form, as
// nlohmann::json writes them).
void stream_json_arrays(Sink& sink, const std::vector<double>& angles, const std::vector<scatter::Complex>& s1,
                        const std::vector<scatter::Complex>& s2, const scatter::MuellerElements* mm) {
  auto& b = sink.buffer();
  const auto array = [&](const char* name, const auto& each) {
    fmt::format_to(std::back_inserter(b), ",\"{}\":[", name);
    for (std::size_t i = 0; i < angles.size(); ++i) {
      if (i) b += ',';
      each(i);
      sink.flush();
    }
    b += ']';
  };
  array("angles_deg", [&](std::size_t i) { fmt::format_to(std::back_inserter(b), "{}", angles[i]); });
  array("s1", [&](std::size_t i) { fmt::format_to(std::back_inserter(b), "[{},{}]", s1[i].real(), s1[i].imag()); });
  array("s2", [&](std::size_t i) { fmt::format_to(std::back_inserter(b), "[{},{}]", s2[i].real(), s2[i].imag()); });
  if (!mm) return;
  const std::pair<const char*, const std::vector<double>*> elements[] = {
      {"s11", &mm->s11}, {"s12", &mm->s12}, {"s33", &mm->s33}, {"s34", &mm->s34}};
  for (const auto& e : elements)
    array(e.first, [&](std::size_t i) { fmt::format_to(std::back_inserter(b), "{}", (*e.second)[i]); });
}

// The efficiencies and the problem as a JSON object's members, without the closing brace.
std::string json_head(double x, scatter::Complex m, int terms, const scatter::MieEfficiencies& q,
                      std::optional<int> debye) {
  nlohmann::ordered_json j;
  j["x"] = x;
  j["m"] = {m.real(), m.imag()};
  j["n_terms"] = terms;
  j["qext"] = q.qext;
  j["qsca"] = q.qsca;
  j["qabs"] = q.qabs;
  j["qback"] = q.qback;
  j["g"] = q.g;
  if (debye) j["debye_p"] = *debye;
  std::string s = j.dump();
  s.pop_back();  // the closing brace: members follow
  return s;
}

enum class FileFormat { csv, npy, json, netcdf };

FileFormat output_format(const std::string& path) {
  const std::string ext = io::lower_extension(path);  // as every output's format: whatever the case
  if (ext == ".csv") return FileFormat::csv;
  if (ext == ".npy") return FileFormat::npy;
  if (ext == ".json") return FileFormat::json;
  if (ext == ".nc") return FileFormat::netcdf;
  throw Error(fmt::format("-o {}: the amplitudes are written as .csv, .npy, .json or .nc (NetCDF-4); give one of "
                          "those extensions",
                          printable(path)));
}

int run_mie(const MieArgs& a) {
  const scatter::MieRequest& r = *a.r;
  const bool dimensionless = !a.m_text.empty() || r.x;
  const bool physical = a.radius_um || a.wavelength_nm;
  if (dimensionless && physical)
    throw Error("give either --m and --x, or --radius-um and --wavelength-nm (with --medium), not both");
  if (a.output && a.output->empty()) throw Error("-o: give a file name (.csv, .npy, .json or .nc)");
  if (r.no_angles && a.output) throw Error("-o writes the amplitudes; --no-angles computes none");
  if (r.no_angles && r.debye) throw Error("--debye restricts the amplitudes; --no-angles computes none");
  if (r.no_angles && r.mueller) throw Error("--mueller derives from the amplitudes; --no-angles computes none");
  scatter::Complex m;
  double x = 0;
  if (physical) {
    if (!a.radius_um || !a.wavelength_nm) throw Error("--radius-um and --wavelength-nm go together");
    const auto sphere = medium_flag("--medium", a.medium);
    const auto outside = medium_flag("--surrounding", a.surrounding);
    check_temperature_flag(r.temperature_c, {sphere.get(), outside.get()});
    const auto p = scatter::sphere_problem(*a.radius_um, *a.wavelength_nm, *sphere, *outside, r.temperature_c);
    m = p.m;
    x = p.x;
  } else {
    if (a.m_text.empty() || !r.x) throw Error("--m and --x go together (or use --radius-um and --wavelength-nm)");
    m = parse_complex(a.m_text, "--m");
    x = *r.x;
  }
  std::vector<double> angles, mu;
  if (!r.no_angles) {
    angles = parse_angles_deg(a.angles, "--angles-deg");
    mu.resize(angles.size());
    for (std::size_t i = 0; i < mu.size(); ++i) mu[i] = std::cos(deg_to_rad(angles[i]));
  }
  // The output is reserved before the work (its folder exists and takes a file).
  io::FileSet files;
  io::OutputFile* out_file = nullptr;
  FileFormat format = FileFormat::csv;
  if (a.output) {
    format = output_format(*a.output);
    out_file = &files.output("-o", *a.output);
    if (format == FileFormat::netcdf) (void)io::netcdf_api();  // NetCDF support loads now, not after the work
  }

  const auto start = std::chrono::steady_clock::now();
  scatter::MieEfficiencies q;
  int terms = 0;
  std::vector<scatter::Complex> s1(mu.size()), s2(mu.size());
  try {
    if (r.no_angles) {
      terms = scatter::mie_terms(x);
      q = scatter::mie_efficiencies(m, x);
    } else {
      const scatter::MieCoefficients c = scatter::mie_coefficients(m, x);
      terms = c.terms();
      q = scatter::mie_efficiencies(c);  // of the whole sphere, also with --debye
      ProgressBar bar("mie", a.quiet);
      scatter::mie_amplitudes(r.debye ? scatter::debye_coefficients(m, x, *r.debye) : c, mu, s1, s2, r.threads,
                              bar.callback());
      bar.finish();
    }
  } catch (const DomainError& e) {
    if (!physical) throw;
    // In the physical form the solver's limits on x and m come from the drop and the light.
    const std::string flags = e.quantity() == "x" ? "--radius-um/--wavelength-nm (size parameter x)"
                                                  : "--medium/--surrounding (relative index m)";
    throw Error(fmt::format("{}: {} = {:g} is {}", flags, e.quantity(), e.value(), e.range_text()));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::optional<scatter::MuellerElements> mueller;
  if (r.mueller) mueller = scatter::mueller_elements(s1, s2);
  const scatter::MuellerElements* mm = mueller ? &*mueller : nullptr;

  // The amplitudes to the file, in its format, streamed.
  if (out_file) {
    Sink sink(out_file);
    auto& b = sink.buffer();
    if (format == FileFormat::netcdf) {
      scatter::MieDatasetInput in = scatter::one_sphere(m, x, q, terms, angles, s1, s2, mm);
      in.debye_p = r.debye;
      if (physical) {
        in.wavelength_nm = a.wavelength_nm;
        in.radius_um = std::span<const double>(&*a.radius_um, 1);
        in.medium = a.medium, in.surrounding = a.surrounding, in.temperature_c = r.temperature_c;
      }
      b = io::netcdf_api().encode(scatter::mie_dataset(in, history_line(command_line())));
    } else if (format == FileFormat::npy) {
      const std::size_t columns = mm ? 9 : 5;
      const std::size_t shape[2] = {angles.size(), columns};
      b = io::npy_header_f8(shape);
      for (std::size_t i = 0; i < angles.size(); ++i) {
        double row[9] = {angles[i], s1[i].real(), s1[i].imag(), s2[i].real(), s2[i].imag()};
        if (mm) row[5] = mm->s11[i], row[6] = mm->s12[i], row[7] = mm->s33[i], row[8] = mm->s34[i];
        io::append_f8_le(b, std::span<const double>(row, columns));
        sink.flush();
      }
    } else if (format == FileFormat::csv) {
      b = mm ? "theta_deg,s1_re,s1_im,s2_re,s2_im,s11,s12,s33,s34\n" : "theta_deg,s1_re,s1_im,s2_re,s2_im\n";
      for (std::size_t i = 0; i < angles.size(); ++i) {
        fmt::format_to(std::back_inserter(b), "{},{},{},{},{}", angles[i], s1[i].real(), s1[i].imag(), s2[i].real(),
                       s2[i].imag());
        if (mm) fmt::format_to(std::back_inserter(b), ",{},{},{},{}", mm->s11[i], mm->s12[i], mm->s33[i], mm->s34[i]);
        b += '\n';
        sink.flush();
      }
    } else {
      b = json_head(x, m, terms, q, r.debye);
      stream_json_arrays(sink, angles, s1, s2, mm);
      fmt::format_to(std::back_inserter(b), ",\"compute_s\":{}}}\n", seconds);
    }
    sink.flush(true);
    files.commit();
  }

  if (a.json) {
    Sink sink(nullptr);
    auto& b = sink.buffer();
    b = json_head(x, m, terms, q, r.debye);
    if (out_file)
      fmt::format_to(std::back_inserter(b), ",\"output\":{}", nlohmann::json(*a.output).dump());
    else if (!r.no_angles)
      stream_json_arrays(sink, angles, s1, s2, mm);
    fmt::format_to(std::back_inserter(b), ",\"compute_s\":{}}}\n", seconds);
    sink.flush(true);
    return 0;
  }
  fmt::print("x = {:.10g}, m = {:.8g}{:+.4g}i, {} terms, computed in {:.3g} s\n", x, m.real(), m.imag(), terms,
             seconds);
  fmt::print("Qext = {:.10g}  Qsca = {:.10g}  Qabs = {:.6g}  Qback = {:.8g}  g = {:.10g}\n", q.qext, q.qsca,
             q.qabs, q.qback, q.g);
  if (r.no_angles) return 0;
  if (out_file) {
    fmt::print("S1, S2{} at {} angles written to {}\n", mm ? " and S11, S12, S33, S34" : "", angles.size(),
               *a.output);
    return 0;
  }
  if (r.debye) fmt::print("amplitudes of Debye order p = {} alone\n", *r.debye);
  Sink sink(nullptr);
  auto& b = sink.buffer();
  fmt::format_to(std::back_inserter(b), "{:>10}  {:>16}  {:>16}  {:>16}  {:>16}", "theta_deg", "Re S1", "Im S1",
                 "Re S2", "Im S2");
  if (mm) fmt::format_to(std::back_inserter(b), "  {:>16}  {:>16}  {:>16}  {:>16}", "S11", "S12", "S33", "S34");
  b += '\n';
  for (std::size_t i = 0; i < mu.size(); ++i) {
    fmt::format_to(std::back_inserter(b), "{:>10.4f}  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", angles[i],
                   s1[i].real(), s1[i].imag(), s2[i].real(), s2[i].imag());
    if (mm)
      fmt::format_to(std::back_inserter(b), "  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", mm->s11[i], mm->s12[i],
                     mm->s33[i], mm->s34[i]);
    b += '\n';
    sink.flush();
  }
  sink.flush(true);
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
  Command cmd{sub,
              [args] { return run_mie(*args); },
              {{"x", "--x"},
               {"m_real", "--m (real part)"},
               {"m_imag", "--m (imaginary part)"},
               {"m_abs", "--m (its modulus)"},
               {"radius_um", "--radius-um"},
               {"wavelength_nm", "--wavelength-nm"},
               {"temperature_c", "--temperature-c"}}};
  // The declared parameters (x; temperature_c; no_angles, debye, mueller, threads) among this command's own.
  const auto params = scatter::mie_params();
  const auto declared = [&](std::size_t from, std::size_t count) {
    add_params(*sub, args->r, params.subspan(from, count), cmd.flags_for_quantity);
  };
  auto* m_opt = sub->add_option("--m", args->m_text,
                                 "Relative complex index n+ki (k >= 0 absorbing; n, k up to 1000, |m| >= 0.001), "
                                 "e.g. 1.333+1e-8i or 10+10i");
  declared(0, 1);
  sub->add_option("--radius-um", args->radius_um, "Sphere radius, micrometres")
      ->check(positive_number(1e6, "um"));
  sub->add_option("--wavelength-nm", args->wavelength_nm, "Vacuum wavelength, nanometres")
      ->check(positive_number(1e6, "nm"));
  auto* medium_opt =
      sub->add_option("--medium", args->medium, "Sphere medium (see hydrolux ior --list)")->capture_default_str();
  auto* surrounding_opt =
      sub->add_option("--surrounding", args->surrounding, "Surrounding medium (air, or const:1 for vacuum)")
          ->capture_default_str();
  declared(1, 1);
  // The dimensionless form takes m and x as they are: media flags would be silently ignored.
  for (auto* o : {m_opt, sub->get_option("--x")})
    o->excludes(medium_opt)->excludes(surrounding_opt)->excludes(sub->get_option("--temperature-c"));
  sub->add_option("--angles-deg", args->angles,
                  "Scattering angles, degrees (0 = forward): A:B:N for N angles from A to B (N from 2 to 1e6, or 1 with "
                  "A == B), or a list 0,10,90, strictly increasing or decreasing")
      ->capture_default_str();
  declared(2, 4);
  sub->add_option("-o,--output", args->output,
                  "Write S1, S2 to this file instead of printing them, by extension: .csv (theta_deg,s1_re,s1_im,"
                  "s2_re,s2_im[,s11,s12,s33,s34 with --mueller]), .npy (float64 array, one row per angle, the same "
                  "five or nine columns), .json (the --json object) or .nc (NetCDF-4 with CF attributes: the "
                  "efficiencies, S1, S2 as real and imaginary parts, the Mueller elements, the phase function "
                  "normalised to 1 over the sphere); written whole or not at all");
  sub->add_flag("--json", args->json,
                "Print one JSON object: x, m, n_terms, qext, qsca, qabs, qback, g, [debye_p,] angles_deg, "
                "s1, s2 ([re, im] pairs), [s11, s12, s33, s34 with --mueller] (with -o: \"output\", the file, "
                "instead of the arrays), compute_s (seconds of "
                "computation alone); streamed, so a million angles need no more memory than their values");
  sub->add_flag("-q,--quiet", args->quiet, "No progress bar on stderr");
  return cmd;
}

}  // namespace hydrolux::cli
