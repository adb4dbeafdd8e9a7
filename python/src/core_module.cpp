// hydrolux._core: the physics with numpy in and out. The Python layer (python/hydrolux/__init__.py)
// gives each function its documented signature, defaults and result type; this module does the work
// with the GIL released for anything long. No image files here: those are in hydrolux._image, which
// loads OpenImageIO (~260 libraries) only for the code that needs it.
#include "bindings.hpp"
#include "hydrolux/version.hpp"

PYBIND11_MODULE(_core, m) {
  using namespace hydrolux::py_bind;
  register_errors();
  m.doc() = "hydrolux's physics with numpy in and out (use the hydrolux package, which documents each call)";
  m.attr("__version__") = hydrolux::kVersion;
  bind_optics(m);
  bind_scatter(m);
  bind_atmos(m);
  bind_drop(m);
  bind_rain(m);
  bind_fog(m);
  bind_scene(m);
  bind_core(m);
}
