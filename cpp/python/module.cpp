// The compiled half of the `ifsforge` Python package (OpenVDB aside: see bind_io_vdb.cpp).
#include "bindings.h"

PYBIND11_MODULE(_core, m) {
  using namespace ifsforge::python;
  m.doc() = "ifsforge core: iterated function systems in n dimensions, their analysis and rendering";
  bind_core(m);
  bind_model(m);
  bind_render(m);
  bind_texture(m);
  bind_vector(m);
  bind_volume(m);
  bind_io(m);
  bind_terrain(m);
  bind_pifs(m);
  bind_design(m);
  bind_inverse(m);
  bind_distributed(m);
}
