#pragma once
// One sphere's Lorenz-Mie scattering as `hydrolux mie` reports it: the solution
// (scatter/mie_solution.hpp) written to -o in its format (.csv, .npy, .json or NetCDF-4 .nc), and the
// summary, the amplitudes' table or the --json object on standard output, each streamed in pieces of
// about a megabyte, so that a million angles never sit in memory as text. The output is reserved before
// the work (io/files.hpp). The CLI parses its flags (the index or the sphere, the angles) into a MieJob
// and hands the job its standard output; the messages name the flags.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/params.hpp"

namespace hydrolux::io {

struct MieJob {
  scatter::MieRequest request;  // the declared values: no_angles, debye, mueller, threads, temperature_c
  scatter::Complex m;           // the problem: --m and --x, or the sphere's (scatter::sphere_problem)
  double x = 0;
  // The physical form (--radius-um, --wavelength-nm, --medium, --surrounding): the solver's limits on x
  // and m are then said in those flags, and a NetCDF file records them.
  struct Sphere {
    double radius_um = 0, wavelength_nm = 0;
    std::string medium, surrounding;
  };
  std::optional<Sphere> sphere;
  std::vector<double> angles_deg;     // the scattering angles; empty with request.no_angles
  std::optional<std::string> output;  // -o: .csv, .npy, .json or .nc by its extension, whatever the case
  bool json = false;                  // --json: one JSON object on standard output instead of the text
  std::string command_line;           // the call, for a NetCDF file's history (core/dataset.hpp's history_line)
};

struct MieJobHooks {
  // Standard output: the bytes in order, in pieces (IoFailure when they cannot be written).
  std::function<void(std::string_view)> out;
  std::function<void(double, std::string_view)> progress;  // the amplitudes' work; may be empty
  std::function<void()> finish_progress;
};

// Runs the job: -o's extension checked and the file reserved (NetCDF support loaded then), the sphere
// solved (DomainError, or Error in the sphere's flags in the physical form), the file written and
// committed, then standard output: with --json the object (x, m, n_terms, qext, qsca, qabs, qback, g,
// [debye_p], the arrays or "output", compute_s); else two lines of the problem and the efficiencies and
// the amplitudes' table (or the line naming the file written).
void run_mie_job(const MieJob& job, const MieJobHooks& hooks);

}  // namespace hydrolux::io
