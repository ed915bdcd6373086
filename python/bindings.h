// The pieces of the _aperture extension module (python/module.cpp) and what
// they share: DEMs from NumPy arrays, results back as NumPy arrays.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include "aperture/python/dem_array.h"

namespace aal::python {

// A vector handed to NumPy without a copy: the array owns it.
template <class T>
pybind11::array_t<T> toNumpy(std::vector<T>&& values, std::vector<pybind11::ssize_t> shape) {
  auto owner = std::make_unique<std::vector<T>>(std::move(values));
  T* data = owner->data();
  pybind11::capsule free(owner.get(), [](void* p) { delete static_cast<std::vector<T>*>(p); });
  owner.release();
  return pybind11::array_t<T>(std::move(shape), data, free);
}

// Takes the DEM out of a _Dem object (made by aperture's Python side for one
// call): its samples move into the heightfield rather than being copied.
DemArray takeDem(DemArray& dem);

void addBakeFunctions(pybind11::module_& m);   // _bake, _relief
void addRenderFunction(pybind11::module_& m);  // _render

}  // namespace aal::python
