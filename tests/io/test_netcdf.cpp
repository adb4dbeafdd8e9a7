// NetCDF-4 files of labelled datasets (io/netcdf.hpp, core/dataset.hpp): the coder round-trips every
// type exactly, and the Lee and Mie datasets hold what their tables hold, with CF attributes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "hydrolux/atmos/lee.hpp"
#include "hydrolux/core/dataset.hpp"
#include "hydrolux/core/error.hpp"
#include "hydrolux/io/lee_files.hpp"
#include "hydrolux/io/netcdf.hpp"
#include "hydrolux/scatter/amplitudes.hpp"
#include "hydrolux/scatter/mie.hpp"
#include "hydrolux/scatter/mie_dataset.hpp"
#include "hydrolux/scatter/mueller.hpp"
#include "hydrolux/version.hpp"

namespace {

using namespace hydrolux;

const io::NetcdfApi& nc() { return *hydrolux_netcdf_api_v1(); }

std::string text_attr(const Attributes& a, std::string_view name) {
  const Attribute* at = a.find(name);
  if (!at) return "<missing>";
  const auto* s = std::get_if<std::string>(&at->value);
  return s ? *s : "<not text>";
}

template <class T>
const std::vector<T>& values(const Dataset& ds, std::string_view name) {
  const Variable* v = ds.find(name);
  if (!v) throw Error(std::string("no variable ") + std::string(name));
  return std::get<std::vector<T>>(v->data);
}

TEST(NetCdf, EveryTypeAndAttributeRoundTripsExactly) {
  Dataset ds;
  ds.dim("row", 2);
  ds.dim("col", 3);
  ds.dim("label", 2);
  ds.add("row", {"row"}, std::vector<double>{0.1, -1e300}).attrs.text("units", "degree");
  ds.add("grid", {"row", "col"}, std::vector<double>{1, 2, 3, 4, 5, std::nextafter(6.0, 7.0)})
      .attrs.text("long_name", "a grid, with UTF-8: \xc2\xb5m")
      .numbers("valid_range", {0, 10});
  ds.add("small", {"col"}, std::vector<float>{1.5f, -0.0f, 3e-38f});
  ds.add("count", {"col"}, std::vector<std::int32_t>{-2147483647 - 1, 0, 2147483647});
  ds.add("label", {"label"}, std::vector<std::string>{"R", "a longer label"});
  ds.add("scalar", {}, std::vector<double>{42.5});
  ds.attrs.text("Conventions", "CF-1.8").integer("seed", (std::int64_t(1) << 53) + 1).number("pi", std::numbers::pi);

  const std::string bytes = nc().encode(ds);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "HDF");  // NetCDF-4 is HDF5 underneath
  const Dataset back = nc().decode(bytes);
  ASSERT_EQ(back.dims, ds.dims);
  EXPECT_EQ(values<double>(back, "grid"), values<double>(ds, "grid"));
  EXPECT_EQ(values<double>(back, "row"), values<double>(ds, "row"));
  EXPECT_EQ(values<float>(back, "small"), values<float>(ds, "small"));
  EXPECT_TRUE(std::signbit(values<float>(back, "small")[1]));
  EXPECT_EQ(values<std::int32_t>(back, "count"), values<std::int32_t>(ds, "count"));
  EXPECT_EQ(values<std::string>(back, "label"), values<std::string>(ds, "label"));
  EXPECT_EQ(values<double>(back, "scalar"), std::vector<double>{42.5});
  EXPECT_TRUE(back.find("scalar")->dims.empty());
  EXPECT_EQ(text_attr(back.find("grid")->attrs, "long_name"), "a grid, with UTF-8: \xc2\xb5m");
  EXPECT_EQ(std::get<std::vector<double>>(back.find("grid")->attrs.find("valid_range")->value),
            (std::vector<double>{0, 10}));
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(back.attrs.find("seed")->value)[0], (std::int64_t(1) << 53) + 1);
  EXPECT_EQ(std::get<std::vector<double>>(back.attrs.find("pi")->value)[0], std::numbers::pi);
  EXPECT_EQ(text_attr(back.attrs, "Conventions"), "CF-1.8");
  // No fill values: a reader that masks _FillValue has nothing to mask.
  EXPECT_EQ(back.find("grid")->attrs.find("_FillValue"), nullptr);
}

TEST(NetCdf, MalformedDatasetsAndBytesAreErrors) {
  Dataset wrong_size;
  wrong_size.dim("n", 3);
  wrong_size.add("v", {"n"}, std::vector<double>{1, 2});
  EXPECT_THROW((void)nc().encode(wrong_size), Error);
  Dataset no_dim;
  no_dim.add("v", {"m"}, std::vector<double>{1});
  EXPECT_THROW((void)nc().encode(no_dim), Error);
  Dataset bad_name;
  bad_name.dim("n", 1);
  bad_name.add("2bad", {"n"}, std::vector<double>{1});
  EXPECT_THROW((void)nc().encode(bad_name), Error);
  Dataset twice;
  twice.dim("n", 1);
  twice.dim("n", 1);
  EXPECT_THROW((void)nc().encode(twice), Error);
  EXPECT_THROW((void)nc().decode("not a NetCDF file at all"), Error);
  EXPECT_THROW((void)nc().decode(""), Error);
  // A real file cut short: an Error, or (where what is left still holds everything the reader
  // needs) the same values; never a crash.
  Dataset ok;
  ok.dim("n", 1000);
  std::vector<double> v(1000);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = std::sin(double(i));
  ok.add("v", {"n"}, v);
  const std::string bytes = nc().encode(ok);
  int refused = 0;
  for (const std::size_t cut : {std::size_t(8), std::size_t(64), std::size_t(512), bytes.size() / 2, bytes.size() - 1})
    try {
      EXPECT_EQ(values<double>(nc().decode(std::string_view(bytes).substr(0, cut)), "v"), v) << cut;
    } catch (const Error&) {
      ++refused;
    }
  EXPECT_GE(refused, 3);
}

// A small corona table with the Stokes Q, through the file and back: the axes, every value and the
// CF attributes as the table holds them.
TEST(NetCdf, LeeTableRoundTripsWithItsAxesUnitsAndHistory) {
  atmos::LeeSpec s = atmos::default_lee_spec(atmos::LeeTableKind::corona);
  s.columns = 5, s.rows = 7, s.wavelengths = 6, s.stokes = true;
  const atmos::LeeTable t = atmos::compute_lee_table(s);
  const atmos::LeeImages im = atmos::lee_images(t);
  const Dataset back = nc().decode(nc().encode(io::lee_dataset(t, im, "the call")));
  EXPECT_EQ(back.dim_size("scattering_angle"), 7u);
  EXPECT_EQ(back.dim_size("radius"), 5u);
  EXPECT_EQ(back.dim_size("wavelength"), 6u);
  EXPECT_EQ(values<double>(back, "radius"), t.radius_um);
  EXPECT_EQ(values<double>(back, "scattering_angle"), t.angle_deg);
  EXPECT_EQ(values<double>(back, "cos_scattering_angle"), t.cos_angle);
  EXPECT_EQ(values<double>(back, "wavelength"), t.wavelengths_nm);
  EXPECT_EQ(values<double>(back, "xyz"), t.xyz);
  EXPECT_EQ(values<double>(back, "q_xyz"), t.q_xyz);
  EXPECT_EQ(values<float>(back, "display"), im.display);
  const auto& rgb = values<double>(back, "rgb");
  const auto& dolp = values<double>(back, "dolp");
  for (int r = 0; r < t.rows(); ++r)
    for (int c = 0; c < t.columns(); ++c) {
      const auto v = t.rgb(r, c);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(rgb[(std::size_t(r) * 5 + std::size_t(c)) * 3 + std::size_t(k)], v[std::size_t(k)]);
      EXPECT_EQ(dolp[std::size_t(r) * 5 + std::size_t(c)], t.dolp(r, c));
    }
  EXPECT_EQ(back.find("rgb")->dims, (std::vector<std::string>{"scattering_angle", "radius", "channel"}));
  EXPECT_EQ(values<std::string>(back, "channel"), (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(text_attr(back.find("rgb")->attrs, "units"), "sr-1");
  EXPECT_EQ(text_attr(back.find("radius")->attrs, "units"), "um");
  EXPECT_EQ(text_attr(back.find("scattering_angle")->attrs, "units"), "degree");
  EXPECT_EQ(text_attr(back.find("wavelength")->attrs, "standard_name"), "radiation_wavelength");
  for (const auto& v : back.variables) EXPECT_NE(text_attr(v.attrs, "long_name"), "<missing>") << v.name;
  EXPECT_EQ(text_attr(back.attrs, "Conventions"), "CF-1.8");
  EXPECT_EQ(text_attr(back.attrs, "history"), "the call");
  EXPECT_EQ(text_attr(back.attrs, "table"), "corona");
  EXPECT_EQ(text_attr(back.attrs, "theory"), "mie");
}

// The phase function written beside S1 and S2 integrates to 1 over the sphere (Simpson's rule over
// 20,001 angles of a drop of x = 20: the forward peak is ~1/x = 3 degrees wide, 330 samples across;
// the rule's error is far below the 1e-6 asked) and is the library's normalised phase / (4 pi).
TEST(NetCdf, MiePhaseFunctionIntegratesToOneOverTheSphere) {
  const scatter::Complex m(1.333, 1e-8);
  const double x = 20;
  const int n = 20001;
  std::vector<double> angles(n), mu(n);
  for (int i = 0; i < n; ++i) {
    angles[std::size_t(i)] = 180.0 * i / (n - 1);
    mu[std::size_t(i)] = std::cos(angles[std::size_t(i)] * std::numbers::pi / 180);
  }
  const scatter::MieCoefficients c = scatter::mie_coefficients(m, x);
  const scatter::MieEfficiencies q = scatter::mie_efficiencies(c);
  std::vector<scatter::Complex> s1(n), s2(n);
  scatter::mie_amplitudes(c, mu, s1, s2, 1);
  const scatter::MuellerElements mm = scatter::mueller_elements(s1, s2);
  const int terms = c.terms();
  scatter::MieDatasetInput in = scatter::one_sphere(m, x, q, terms, angles, s1, s2, &mm);
  const Dataset back = nc().decode(nc().encode(scatter::mie_dataset(in, "h")));
  const auto& p = values<double>(back, "phase_function");
  const double h = std::numbers::pi / (n - 1);
  double integral = 0;
  for (int i = 0; i < n; ++i) {
    const double w = (i == 0 || i == n - 1) ? 1 : (i % 2 ? 4 : 2);
    integral += w * p[std::size_t(i)] * std::sin(h * i);
  }
  integral *= 2 * std::numbers::pi * h / 3;
  EXPECT_NEAR(integral, 1.0, 1e-6);
  const std::vector<double> reference = scatter::mie_phase_function(c, mu, 1);  // (1/4pi) int = 1
  for (std::size_t i = 0; i < std::size_t(n); i += 997)
    EXPECT_NEAR(p[i], reference[i] / (4 * std::numbers::pi), 1e-12 * reference[i]) << angles[i];
  EXPECT_EQ(values<double>(back, "s11"), mm.s11);
  EXPECT_EQ(values<double>(back, "qext"), std::vector<double>{q.qext});
  EXPECT_EQ(values<std::int32_t>(back, "n_terms"), std::vector<std::int32_t>{terms});
  EXPECT_EQ(text_attr(back.find("phase_function")->attrs, "units"), "sr-1");
  EXPECT_EQ(std::get<std::vector<double>>(back.attrs.find("m_imag")->value)[0], 1e-8);
  // One Debye order's amplitudes are not normalised by the sphere's Qsca: no phase function then.
  in.debye_p = 2;
  EXPECT_EQ(scatter::mie_dataset(in, "h").find("phase_function"), nullptr);
}

// Issue 37: the same dataset makes the same bytes, also a second later (HDF5 can stamp objects with
// times; netCDF-4 turns that off, checked here), and history_line holds no clock: "same inputs, same
// bytes" (README) for the .nc files too. A time only from SOURCE_DATE_EPOCH.
TEST(NetCdf, TheSameDatasetIsTheSameBytesAtAnyTime) {
  atmos::LeeSpec s = atmos::default_lee_spec(atmos::LeeTableKind::corona);
  s.columns = 3, s.rows = 4, s.wavelengths = 4;
  const atmos::LeeTable t = atmos::compute_lee_table(s);
  const atmos::LeeImages im = atmos::lee_images(t);
  ::unsetenv("SOURCE_DATE_EPOCH");
  const std::string first = nc().encode(io::lee_dataset(t, im, history_line("hydrolux lee --table corona")));
  ::usleep(1100000);  // into another second
  const std::string second = nc().encode(io::lee_dataset(t, im, history_line("hydrolux lee --table corona")));
  EXPECT_EQ(first, second);
  EXPECT_EQ(history_line("x"), std::string("hydrolux ") + kVersion + ": x");
  ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
  EXPECT_EQ(history_line("x"), std::string("2023-11-14T22:13:20Z hydrolux ") + kVersion + ": x");
  for (const char* not_a_time : {"", "abc", "-1", "1.5", "1e30"}) {
    ::setenv("SOURCE_DATE_EPOCH", not_a_time, 1);
    EXPECT_EQ(history_line("x"), std::string("hydrolux ") + kVersion + ": x") << not_a_time;
  }
  ::unsetenv("SOURCE_DATE_EPOCH");
}

// Issue 37: a coordinate (a variable over the one dimension of its name) that repeats or turns back
// is not CF: refused by the dataset, and by the Mie dataset naming its argument (Python's
// MieResult.to_xarray() and hydrolux mie -o p.nc build it).
TEST(NetCdf, CoordinatesMustBeStrictlyMonotonic) {
  for (const auto& v : {std::vector<double>{10, 10, 20}, std::vector<double>{0, 90, 45}}) {
    Dataset ds;
    ds.dim("scattering_angle", 3);
    ds.add("scattering_angle", {"scattering_angle"}, v);
    EXPECT_THROW(ds.check(), Error);
    EXPECT_THROW((void)nc().encode(ds), Error);
  }
  Dataset down;  // decreasing is monotonic; an auxiliary variable may repeat
  down.dim("scattering_angle", 3);
  down.add("scattering_angle", {"scattering_angle"}, std::vector<double>{180, 90, 0});
  down.add("cos_scattering_angle", {"scattering_angle"}, std::vector<double>{1, 1, 1});
  EXPECT_NO_THROW(down.check());
  const scatter::Complex m(1.333, 0);
  const double x = 10;
  const std::vector<double> angles{10, 10, 20};
  std::vector<double> mu;
  for (double a : angles) mu.push_back(std::cos(a * std::numbers::pi / 180));
  const scatter::MieCoefficients c = scatter::mie_coefficients(m, x);
  std::vector<scatter::Complex> s1(3), s2(3);
  scatter::mie_amplitudes(c, mu, s1, s2, 1);
  const int terms = c.terms();
  const scatter::MieDatasetInput in =
      scatter::one_sphere(m, x, scatter::mie_efficiencies(c), terms, angles, s1, s2, nullptr);
  try {
    (void)scatter::mie_dataset(in, "h");
    ADD_FAILURE() << "repeated angles accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("angles_deg: 10 is repeated", 0), 0u) << e.what();
  }
}

}  // namespace
