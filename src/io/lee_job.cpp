// hydrolux lee's run: see hydrolux/io/lee_job.hpp.
#include "hydrolux/io/lee_job.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>

#include "hydrolux/atmos/lee_params.hpp"
#include "hydrolux/core/dataset.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/core/parse.hpp"
#include "hydrolux/io/files.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/io/netcdf.hpp"

namespace hydrolux::io {

namespace {

// A declared pair (--size, --angle-deg) as the CLI writes it ("512x1024", "130:145"); empty where not given.
template <class T>
std::string given_text(std::string_view name, const std::optional<std::array<T, 2>>& value) {
  return value ? atmos::lee_param(name).value_text({double((*value)[0]), double((*value)[1])}) : std::string();
}

// --radius-um's span "A:B" (A <= B), or one radius R as R:R, if given.
std::optional<std::array<double, 2>> radius_span(const LeeJob& job) {
  if (!job.radius_um) return std::nullopt;
  const std::string& text = *job.radius_um;
  if (const auto v = parse::number(text)) return std::array<double, 2>{*v, *v};
  const auto p = parse::pair(text, ':');
  if (!p || (*p)[1] < (*p)[0])
    throw Error(fmt::format("--radius-um '{}': expected A:B (micrometres in [{:g}, {:g}], A <= B) or one value", text,
                            atmos::kMinRadiusUm, atmos::kMaxRadiusUm));
  return *p;
}

// --wavelengths-nm "A:B" or "A:B:N" set on `s` (the range, and N samples when given).
void set_wavelengths(atmos::LeeSpec& s, const std::string& w) {
  const auto colons = std::count(w.begin(), w.end(), ':');
  const auto bad = [&] {
    return Error(fmt::format("--wavelengths-nm '{}': expected A:B or A:B:N (nanometres in [360, 830], A <= B; N "
                             "samples in [1, 2000])",
                             w));
  };
  std::optional<std::array<double, 2>> p;
  if (colons == 2) {
    const auto last = w.rfind(':');
    p = parse::pair(w.substr(0, last), ':');
    const auto n = parse::integer(w.substr(last + 1));
    if (!n || *n < 1 || *n > 2000) throw bad();
    s.wavelengths = int(*n);
  } else if (colons == 1) {
    p = parse::pair(w, ':');
  }
  if (!p || (*p)[1] < (*p)[0]) throw bad();
  s.wavelength_min_nm = (*p)[0];
  s.wavelength_max_nm = (*p)[1];
}

// -o's files: the .exr and the .png and .json beside it, reserved before the work and written after
// it; or, with a .nc path, the one NetCDF-4 file of io::lee_dataset (its history the command line).
struct LeeOutputs {
  std::string exr_path, png_path, json_path;
  ImageFormat exr_format{}, png_format{};
  OutputFile *exr = nullptr, *png = nullptr, *sidecar = nullptr;
  OutputFile* netcdf = nullptr;  // -o *.nc: the only output

  void write(const atmos::LeeTable& t, const atmos::LeeImages& im, const LeeJob& job, const ImageCodec& codec) const {
    if (netcdf) {
      netcdf->write(netcdf_api().encode(lee_dataset(t, im, history_line(job.command_line))));
      return;
    }
    const LeeFileBytes bytes = encode_lee_files(t, im, codec.encode);
    exr->write(bytes.exr);
    png->write(bytes.png);
    sidecar->write(lee_sidecar(t, im, std::filesystem::path(exr_path).filename().string(),
                               std::filesystem::path(png_path).filename().string())
                       .dump(1) +
                   "\n");
  }
  std::string describe() const {  // what was written, for the closing line
    if (netcdf) return printable(netcdf->target().string());
    return fmt::format("{}, {} and {}", printable(exr_path), printable(png_path), printable(json_path));
  }
};

LeeOutputs declare_lee_outputs(FileSet& files, const std::string& exr_path, const LeeJobHooks& h) {
  const std::filesystem::path p(exr_path);
  LeeOutputs o;
  const std::string ext = lower_extension(p);  // as every output's format: whatever the case
  if (ext == ".nc") {
    o.netcdf = &files.output("-o", exr_path);
    (void)netcdf_api();  // NetCDF support loads now, not after the work
    return o;
  }
  if (ext != ".exr")
    throw Error(fmt::format("-o {}: give a .exr path (the table as OpenEXR, with a .png and a .json beside it) or a "
                            ".nc path (one NetCDF-4 file with CF attributes)",
                            printable(exr_path)));
  o.exr_path = exr_path;
  o.png_path = std::filesystem::path(p).replace_extension(".png").string();
  o.json_path = std::filesystem::path(p).replace_extension(".json").string();
  o.exr_format = output_image_format(o.exr_path, "-o");
  o.exr = &files.output("-o", o.exr_path);
  o.png_format = output_image_format(o.png_path, "-o (its .png)");
  o.png = &files.output("-o (its .png)", o.png_path);
  o.sidecar = &files.output("-o (its .json)", o.json_path);
  if (h.codec_ready) h.codec_ready();  // image support loads now, not after the work
  return o;
}

// The checks of a spec whose medium the door has checked, in the flags' words.
void check_lee_job(const LeeJob& job, atmos::LeeSpec& s) {
  try {
    s.sun = color::Illuminant::parse(job.sun);
  } catch (const DomainError& e) {
    throw Error(fmt::format("--sun {}: {:g} K is {}", job.sun, e.value(), e.range_text()));
  } catch (const Error& e) {
    throw Error(fmt::format("--sun: {}", e.what()));
  }
  s.rgb_space = color::parse_rgb_space(job.color_space);
  if (job.given.count("limb_darkening") && s.sun_disk_deg == 0)
    throw Error("--limb-darkening: --sun-disk-deg 0 makes the sun a point, which has no limb to darken");
  if (job.given.count("radius_scale") && s.columns == 1)
    throw Error(fmt::format("--radius-scale {}: a table of one column has no column spacing",
                            atmos::radius_scale_name(job.request.radius_scale)));
  if (job.radius_um) {
    // The largest radius depends on the theory, the spread and the shortest wavelength (the size
    // parameter's limit): stated with them, instead of as a size parameter out of range.
    const double rmax = atmos::max_radius_um(s);
    if (s.radius_max_um > rmax && s.radius_max_um <= atmos::kMaxRadiusUm)
      throw Error(fmt::format("--radius-um {}: {:g} um is outside the valid range [{:g}, {:g}] um for --theory {}, "
                              "--size-spread {:g} and {:g} nm (the largest drops' size parameter 2 pi r n / lambda "
                              "must stay within the theory's limit)",
                              *job.radius_um, s.radius_max_um, atmos::kMinRadiusUm, rmax,
                              scatter::theory_name(s.theory), s.size_spread, s.wavelength_min_nm));
  }
  atmos::validate(s);
  atmos::check_table_memory({&s}, job.request.size ? given_text("size", job.request.size)
                                                  : fmt::format("{}x{} (the default)", s.columns, s.rows),
                            atmos::SizeSyntax::cli);
  if (!job.json && job.output.empty())
    throw Error("-o is required (a .exr path, or .nc for NetCDF), unless --json prints a profile");
  const auto radii = radius_span(job);
  if (job.json && !(radii && (*radii)[0] == (*radii)[1])) throw Error("--json prints one radius's profile: give a single --radius-um R");
}

}  // namespace

atmos::LeeSpec lee_job_spec(const LeeJob& job) {
  atmos::LeeRequest req = job.request;
  try {
    req.theory = scatter::parse_theory(job.theory);
  } catch (const Error& e) {
    throw Error(fmt::format("--theory {}: {}", job.theory, e.what()));
  }
  bool spheres = true;
  try {
    spheres = atmos::parse_drop_shape(req.shape).spherical();
  } catch (const Error& e) {
    throw Error(fmt::format("--{}", e.what()));  // the library's message starts "shape '<value>': "
  }
  // The non-spherical drops' parameters given for spheres would be ignored (as export refuses them).
  for (const std::string_view name : atmos::kShapeOnlyParams)
    if (spheres && job.given.count(name))
      throw Error(atmos::shape_only_message(name, find_field(atmos::lee_params(), name)->get(req),
                                            atmos::lee_param(name).flag, "--shape"));
  if (job.radius_um) req.radius_um = radius_span(job);
  atmos::LeeSpec s;
  try {
    s = atmos::make_lee_spec(req);
  } catch (const atmos::LeeShapeError& e) {  // said in the flags' words
    if (e.rule() == atmos::LeeShapeError::Rule::one_radius_columns)
      throw Error(fmt::format("--size {}: a single --radius-um {} makes one column; give --size 1x{}",
                              given_text("size", job.request.size), job.radius_um.value_or(""), e.rows()));
    throw Error(fmt::format("--angle-deg {}: a table of {} rows needs A < B (or --size Wx1 for one angle)",
                            given_text("angle_deg", job.request.angle_deg), e.rows()));
  }
  if (!s.shape.spherical() &&
      (s.table != atmos::LeeTableKind::rainbow || s.theory.kind != scatter::TheoryKind::Airy || s.theory.p > 3))
    throw Error(fmt::format("--shape {}: non-spherical drops are computed by Airy theory of their plane section "
                            "(docs/non-spherical.md): give --theory airy (primary) or airy:3 (secondary) with "
                            "--table rainbow, not --table {} --theory {}",
                            req.shape, atmos::table_kind_name(req.table), job.theory));
  set_wavelengths(s, job.wavelengths);
  s.drop_medium = job.medium;
  return s;
}

LeeJobResult run_lee_job(const LeeJob& job, atmos::LeeSpec s, const LeeJobHooks& h) {
  check_lee_job(job, s);
  // Every output is reserved before the work: the EXR, and the PNG and JSON beside it.
  FileSet files;
  std::optional<LeeOutputs> out;
  if (!job.output.empty()) out = declare_lee_outputs(files, job.output, h);
  const std::vector<std::string> before = atmos::lee_resolution_notes(s);
  if (h.warn)
    for (const auto& note : before) h.warn(note);

  const auto start = std::chrono::steady_clock::now();
  const atmos::LeeTable t = atmos::compute_lee_table(s, h.progress);
  if (h.finish_progress) h.finish_progress();
  LeeJobResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const atmos::LeeImages im = atmos::lee_images(t);
  if (out) {
    out->write(t, im, job, h.codec);
    files.commit();
    r.written = out->describe();
  }
  // What only the table itself shows (its estimated error above the tolerance), once it is computed
  // and written: a failure to write stays one line.
  if (h.warn)
    for (std::size_t i = before.size(); i < t.notes.size(); ++i) h.warn(t.notes[i]);
  if (job.json && h.out) h.out(lee_profile_json(t).dump() + "\n");
  r.columns = t.columns();
  r.rows = t.rows();
  r.theory = scatter::theory_name(s.theory);
  r.work = t.work;
  r.error = t.error;
  r.sampling = t.spec.sampling;
  r.first_sampling = t.first_sampling;
  r.first_error = t.first_error;
  return r;
}

std::string lee_summary(const LeeJobResult& r) {
  return fmt::format("lee: wrote {} ({}x{}, {}) in {:.1f} s ({} evaluations, {:.3g} terms x angles{}{})", r.written,
                     r.columns, r.rows, r.theory, r.seconds, r.work.evaluations, double(r.work.term_angles),
                     r.error.luminance_rms
                         ? fmt::format("; estimated error {:.2g}% RMS in luminance", 100 * *r.error.luminance_rms)
                         : std::string(),
                     r.first_sampling && r.first_error
                         ? fmt::format("; at sampling {:g}, chosen because {:g} gave {:.2g}%", r.sampling,
                                       *r.first_sampling, 100 * *r.first_error)
                         : std::string());
}

}  // namespace hydrolux::io
