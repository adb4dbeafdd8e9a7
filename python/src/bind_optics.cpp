// hydrolux._core: interface optics (optics/fresnel.hpp) and the media (optics/media.hpp).
#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <memory>
#include <optional>
#include <string>

#include "bindings.hpp"
#include "hydrolux/core/math.hpp"
#include "hydrolux/optics/fresnel.hpp"
#include "hydrolux/optics/media.hpp"

namespace hydrolux::py_bind {

std::shared_ptr<const optics::Medium> medium_arg(const char* arg, const std::string& name) {
  try {
    return optics::find_medium(name);
  } catch (const UnknownNameError& e) {
    throw UnknownNameError(fmt::format("{}: {}", arg, e.what()));
  } catch (const DomainError& e) {
    throw Error(fmt::format("{} {}: {} {:g} is {}", arg, name, e.quantity(), e.value(), e.range_text()));
  }
}

namespace {

// ---- interface optics -----------------------------------------------------------------------

py::dict fresnel(py::handle theta_arg, double n1, double n2, double k2) {
  const DoubleArray theta_deg = c_array<double>(theta_arg, "theta_deg");
  require_arg("n1", n1, 1e-3, 1000);
  require_arg("n2", n2, 1e-3, 1000);
  require_arg("k2", k2, 0, 1000);
  const auto shape = shape_of(theta_deg);
  DoubleArray rs(shape), rp(shape), r(shape), t(shape), theta_t(shape);
  py::array_t<bool> tir(shape);
  const double* th = theta_deg.data();
  for (py::ssize_t i = 0; i < theta_deg.size(); ++i) require_arg("theta_deg", th[i], 0, 90, "deg");
  const double nan = std::nan("");
  for (py::ssize_t i = 0; i < theta_deg.size(); ++i) {
    const double cos_i = std::cos(deg_to_rad(th[i]));
    if (k2 > 0) {
      const auto f = optics::fresnel_conductor(cos_i, n1, std::complex<double>(n2, k2));
      rs.mutable_data()[i] = f.R_s, rp.mutable_data()[i] = f.R_p, r.mutable_data()[i] = f.R;
      t.mutable_data()[i] = nan, theta_t.mutable_data()[i] = nan, tir.mutable_data()[i] = false;
    } else {
      const auto f = optics::fresnel_dielectric(cos_i, n1, n2);
      rs.mutable_data()[i] = f.R_s, rp.mutable_data()[i] = f.R_p, r.mutable_data()[i] = f.R;
      t.mutable_data()[i] = f.T;
      theta_t.mutable_data()[i] = f.tir ? nan : rad_to_deg(safe_acos(f.cos_t));
      tir.mutable_data()[i] = f.tir;
    }
  }
  py::dict d;
  d["theta_t_deg"] = theta_t, d["rs"] = rs, d["rp"] = rp, d["r"] = r, d["t"] = t, d["tir"] = tir;
  return d;
}

py::list media() {
  py::list out;
  for (const auto& name : optics::medium_names()) {
    const auto& i = optics::find_medium(name)->info();
    py::dict d;
    d["medium"] = i.name, d["description"] = i.description, d["source"] = i.source;
    d["wavelength_nm"] = py::make_tuple(i.lambda_min_nm, i.lambda_max_nm);
    d["temperature_c"] = py::make_tuple(i.temperature_min_c, i.temperature_max_c);
    d["default_temperature_c"] = i.default_temperature_c;
    d["temperature_dependent"] = i.temperature_dependent;
    d["conductor"] = i.conductor;
    out.append(d);
  }
  return out;
}

ComplexArray refractive_index(const std::string& medium, py::handle wavelength_arg,
                              std::optional<double> temperature_c) {
  const DoubleArray wavelength_nm = c_array<double>(wavelength_arg, "wavelength_nm");
  const auto med = medium_arg("medium", medium);
  ComplexArray out(shape_of(wavelength_nm));
  const double* w = wavelength_nm.data();
  for (py::ssize_t i = 0; i < wavelength_nm.size(); ++i) out.mutable_data()[i] = med->index(w[i], temperature_c);
  return out;
}

}  // namespace

void bind_optics(py::module_& m) {
  m.def("fresnel", &fresnel, py::arg("theta_deg"), py::arg("n1"), py::arg("n2"), py::arg("k2"));
  m.def("media", &media);
  m.def("refractive_index", &refractive_index, py::arg("medium"), py::arg("wavelength_nm"), py::arg("temperature_c"));
}

}  // namespace hydrolux::py_bind
