// hydrolux mie's output: see hydrolux/io/mie_job.hpp.
#include "hydrolux/io/mie_job.hpp"

#include <fmt/format.h>

#include <chrono>
#include <iterator>
#include <nlohmann/json.hpp>
#include <span>
#include <utility>

#include "hydrolux/core/dataset.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/netcdf.hpp"
#include "hydrolux/io/npy.hpp"
#include "hydrolux/scatter/mie_dataset.hpp"
#include "hydrolux/scatter/mie_solution.hpp"
#include "hydrolux/scatter/mueller.hpp"

namespace hydrolux::io {

namespace {

using Write = std::function<void(std::string_view)>;

// Where a large output goes (standard output or a reserved output file), in pieces of about a megabyte.
class Sink {
 public:
  explicit Sink(Write write) : write_(std::move(write)) { buffer_.reserve(kChunk + 4096); }
  std::string& buffer() { return buffer_; }
  // Passes the buffer on once it holds a chunk (or always, with force).
  void flush(bool force = false) {
    if (buffer_.empty() || (!force && buffer_.size() < kChunk)) return;
    write_(buffer_);
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kChunk = 1 << 20;
  Write write_;
  std::string buffer_;
};

// What is reported: the problem, its solution, the Mueller elements if asked for.
struct Solved {
  const MieJob& job;
  const scatter::MieSolution& sol;
  const scatter::MuellerElements* mm;
  double seconds;
};

// The JSON object's members after the efficiencies: the angle array and S1, S2 as [re, im] pairs, then
// the Mueller elements if given, streamed (numbers in their shortest round-trip form, as nlohmann::json
// writes them).
void stream_json_arrays(Sink& sink, const Solved& r) {
  auto& b = sink.buffer();
  const auto& angles = r.job.angles_deg;
  const auto& s1 = r.sol.s1;
  const auto& s2 = r.sol.s2;
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
  if (!r.mm) return;
  const std::pair<const char*, const std::vector<double>*> elements[] = {
      {"s11", &r.mm->s11}, {"s12", &r.mm->s12}, {"s33", &r.mm->s33}, {"s34", &r.mm->s34}};
  for (const auto& e : elements)
    array(e.first, [&](std::size_t i) { fmt::format_to(std::back_inserter(b), "{}", (*e.second)[i]); });
}

// The efficiencies and the problem as a JSON object's members, without the closing brace.
std::string json_head(const Solved& r) {
  nlohmann::ordered_json j;
  j["x"] = r.job.x;
  j["m"] = {r.job.m.real(), r.job.m.imag()};
  j["n_terms"] = r.sol.terms;
  j["qext"] = r.sol.q.qext;
  j["qsca"] = r.sol.q.qsca;
  j["qabs"] = r.sol.q.qabs;
  j["qback"] = r.sol.q.qback;
  j["g"] = r.sol.q.g;
  if (r.job.request.debye) j["debye_p"] = *r.job.request.debye;
  std::string s = j.dump();
  s.pop_back();  // the closing brace: members follow
  return s;
}

enum class FileFormat { csv, npy, json, netcdf };

FileFormat output_format(const std::string& path) {
  const std::string ext = lower_extension(path);  // as every output's format: whatever the case
  if (ext == ".csv") return FileFormat::csv;
  if (ext == ".npy") return FileFormat::npy;
  if (ext == ".json") return FileFormat::json;
  if (ext == ".nc") return FileFormat::netcdf;
  throw Error(fmt::format("-o {}: the amplitudes are written as .csv, .npy, .json or .nc (NetCDF-4); give one of "
                          "those extensions",
                          printable(path)));
}

// The amplitudes to the file, in its format, streamed.
void write_amplitudes(OutputFile& file, FileFormat format, const Solved& r) {
  Sink sink([&file](std::string_view bytes) { file.write(bytes); });
  auto& b = sink.buffer();
  const MieJob& job = r.job;
  const auto& angles = job.angles_deg;
  const auto& s1 = r.sol.s1;
  const auto& s2 = r.sol.s2;
  const scatter::MuellerElements* mm = r.mm;
  if (format == FileFormat::netcdf) {
    scatter::MieDatasetInput in = scatter::one_sphere(job.m, job.x, r.sol.q, r.sol.terms, angles, s1, s2, mm);
    in.debye_p = job.request.debye;
    if (job.sphere) {
      in.wavelength_nm = job.sphere->wavelength_nm;
      in.radius_um = std::span<const double>(&job.sphere->radius_um, 1);
      in.medium = job.sphere->medium, in.surrounding = job.sphere->surrounding;
      in.temperature_c = job.request.temperature_c;
    }
    b = netcdf_api().encode(scatter::mie_dataset(in, history_line(job.command_line)));
  } else if (format == FileFormat::npy) {
    const std::size_t columns = mm ? 9 : 5;
    const std::size_t shape[2] = {angles.size(), columns};
    b = npy_header_f8(shape);
    for (std::size_t i = 0; i < angles.size(); ++i) {
      double row[9] = {angles[i], s1[i].real(), s1[i].imag(), s2[i].real(), s2[i].imag()};
      if (mm) row[5] = mm->s11[i], row[6] = mm->s12[i], row[7] = mm->s33[i], row[8] = mm->s34[i];
      append_f8_le(b, std::span<const double>(row, columns));
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
    b = json_head(r);
    stream_json_arrays(sink, r);
    fmt::format_to(std::back_inserter(b), ",\"compute_s\":{}}}\n", r.seconds);
  }
  sink.flush(true);
}

// Standard output: the --json object, or the text (the problem, the efficiencies, the amplitudes' table
// or the file written).
void print_report(const Solved& r, const Write& out) {
  const MieJob& job = r.job;
  const scatter::MieRequest& req = job.request;
  Sink sink(out);
  auto& b = sink.buffer();
  if (job.json) {
    b = json_head(r);
    if (job.output)
      fmt::format_to(std::back_inserter(b), ",\"output\":{}", nlohmann::json(*job.output).dump());
    else if (!req.no_angles)
      stream_json_arrays(sink, r);
    fmt::format_to(std::back_inserter(b), ",\"compute_s\":{}}}\n", r.seconds);
    sink.flush(true);
    return;
  }
  const scatter::MieEfficiencies& q = r.sol.q;
  fmt::format_to(std::back_inserter(b), "x = {:.10g}, m = {:.8g}{:+.4g}i, {} terms, computed in {:.3g} s\n", job.x, job.m.real(),
                 job.m.imag(), r.sol.terms, r.seconds);
  fmt::format_to(std::back_inserter(b), "Qext = {:.10g}  Qsca = {:.10g}  Qabs = {:.6g}  Qback = {:.8g}  g = {:.10g}\n",
                 q.qext, q.qsca, q.qabs, q.qback, q.g);
  const scatter::MuellerElements* mm = r.mm;
  if (!req.no_angles && job.output)
    fmt::format_to(std::back_inserter(b), "S1, S2{} at {} angles written to {}\n",
                   mm ? " and S11, S12, S33, S34" : "", job.angles_deg.size(), *job.output);
  if (req.no_angles || job.output) {
    sink.flush(true);
    return;
  }
  if (req.debye) fmt::format_to(std::back_inserter(b), "amplitudes of Debye order p = {} alone\n", *req.debye);
  fmt::format_to(std::back_inserter(b), "{:>10}  {:>16}  {:>16}  {:>16}  {:>16}", "theta_deg", "Re S1", "Im S1",
                 "Re S2", "Im S2");
  if (mm) fmt::format_to(std::back_inserter(b), "  {:>16}  {:>16}  {:>16}  {:>16}", "S11", "S12", "S33", "S34");
  b += '\n';
  const auto& s1 = r.sol.s1;
  const auto& s2 = r.sol.s2;
  for (std::size_t i = 0; i < s1.size(); ++i) {
    fmt::format_to(std::back_inserter(b), "{:>10.4f}  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", job.angles_deg[i],
                   s1[i].real(), s1[i].imag(), s2[i].real(), s2[i].imag());
    if (mm)
      fmt::format_to(std::back_inserter(b), "  {:>16.9e}  {:>16.9e}  {:>16.9e}  {:>16.9e}", mm->s11[i], mm->s12[i],
                     mm->s33[i], mm->s34[i]);
    b += '\n';
    sink.flush();
  }
  sink.flush(true);
}

}  // namespace

void run_mie_job(const MieJob& job, const MieJobHooks& h) {
  const scatter::MieRequest& req = job.request;
  // The output is reserved before the work (its folder exists and takes a file).
  FileSet files;
  OutputFile* out_file = nullptr;
  FileFormat format = FileFormat::csv;
  if (job.output) {
    format = output_format(*job.output);
    out_file = &files.output("-o", *job.output);
    if (format == FileFormat::netcdf) (void)netcdf_api();  // NetCDF support loads now, not after the work
  }
  std::vector<double> mu(job.angles_deg.size());
  for (std::size_t i = 0; i < mu.size(); ++i) mu[i] = std::cos(deg_to_rad(job.angles_deg[i]));

  const auto start = std::chrono::steady_clock::now();
  scatter::MieSolution sol;
  try {
    sol = scatter::solve_mie(job.m, job.x, mu, req.debye, req.threads, h.progress);
    if (!mu.empty() && h.finish_progress) h.finish_progress();
  } catch (const DomainError& e) {
    if (!job.sphere) throw;
    // In the physical form the solver's limits on x and m come from the drop and the light.
    const std::string flags = e.quantity() == "x" ? "--radius-um/--wavelength-nm (size parameter x)"
                                                  : "--medium/--surrounding (relative index m)";
    throw Error(fmt::format("{}: {} = {:g} is {}", flags, e.quantity(), e.value(), e.range_text()));
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::optional<scatter::MuellerElements> mueller;
  if (req.mueller) mueller = scatter::mueller_elements(sol.s1, sol.s2);
  const Solved r{job, sol, mueller ? &*mueller : nullptr, seconds};
  if (out_file) {
    write_amplitudes(*out_file, format, r);
    files.commit();
  }
  print_report(r, h.out);
}

}  // namespace hydrolux::io
