#pragma once
// Private to hydrolux._core: one bind_* per library module, each in its own bind_<module>.cpp, called
// by core_module.cpp's PYBIND11_MODULE. Every file includes this header, so that each sees the same
// type casters (pybind11/stl.h, complex.h) for the types they share.
#include <pybind11/complex.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "common.hpp"
#include "hydrolux/core/dataset.hpp"

namespace hydrolux::optics {
class Medium;
}

namespace hydrolux::py_bind {

void bind_core(py::module_& m);     // bind_core.cpp: threads, files, memory, the batch helpers
void bind_optics(py::module_& m);   // bind_optics.cpp: fresnel, media, refractive_index
void bind_scatter(py::module_& m);  // bind_scatter.cpp: mie, sphere_problem, SizeDistribution, bulk_optics
void bind_atmos(py::module_& m);    // bind_atmos.cpp: lee
void bind_drop(py::module_& m);     // bind_drop.cpp: drop_render, drop_undistort
void bind_rain(py::module_& m);     // bind_rain.cpp: RainRenderer, builtin_scene
void bind_fog(py::module_& m);      // bind_fog.cpp: fog
void bind_scene(py::module_& m);    // bind_scene.cpp: sky

// A medium by name (optics::find_medium), its errors naming the argument `arg` (bind_optics.cpp).
std::shared_ptr<const optics::Medium> medium_arg(const char* arg, const std::string& name);

// A labelled dataset (core/dataset.hpp) as the package's _xarray module takes it (bind_core.cpp):
// {"dims": [(name, size)], "attrs": {name: value}, "variables": [(name, dims, array, attrs)]}, each
// array numpy of the variable's dims' shape (strings as an object array), each attribute a str, a
// number or a 1-D array of numbers.
py::dict dataset_dict(const Dataset& ds);

}  // namespace hydrolux::py_bind
