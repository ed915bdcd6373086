// _aperture: the compiled half of the Python module `aperture`
// (docs/python.md). Its Python half (python/aperture/__init__.py) checks and
// converts the arguments and documents the functions; this half calls the
// same library functions as the tools, without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "aperture/python/bindings.h"
#include "aperture/python/dem_array.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/raw_dem.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/version.h"

namespace py = pybind11;

namespace aal::python {

DemArray takeDem(DemArray& dem) {
  if (dem.z.empty()) {
    throw std::invalid_argument("dem: this _Dem was used already (make one per call)");
  }
  return std::exchange(dem, DemArray{});
}

namespace {

// The samples (float32, C order: aperture converts any array once) and the
// void flags are copied here, while the GIL is held.
DemArray makeDem(const py::array_t<float, py::array::c_style>& z,
                 const std::optional<py::array_t<uint8_t, py::array::c_style>>& voids, double cellX,
                 double cellY, const std::optional<py::array_t<double, py::array::c_style>>& rows,
                 std::optional<std::array<double, 2>> center, double zScale, double exaggeration) {
  if (z.ndim() != 2) throw std::invalid_argument("dem: a 2-D array is needed");
  // The tools' size limits, before the samples are copied.
  checkDemSize(kDemName, z.shape(1), z.shape(0), kMaxDemTexels);
  DemArray dem;
  dem.height = static_cast<int>(z.shape(0));
  dem.width = static_cast<int>(z.shape(1));
  dem.z.assign(z.data(), z.data() + z.size());
  if (voids) {
    if (voids->ndim() != 2 || voids->shape(0) != z.shape(0) || voids->shape(1) != z.shape(1)) {
      throw std::invalid_argument("dem: the void mask must have the heights' shape");
    }
    dem.voids.assign(voids->data(), voids->data() + voids->size());
  }
  dem.spacing.x = cellX;
  dem.spacing.y = cellY;
  if (rows) dem.spacing.rows.assign(rows->data(), rows->data() + rows->size());
  dem.spacing.center = center;
  dem.zScale = zScale;
  dem.exaggeration = exaggeration;
  return dem;
}

py::tuple solarPositionOf(const std::string& when, double latDeg, double lonDeg) {
  const std::optional<UtcTime> utc = parseIso8601Utc(when);
  if (!utc) {
    throw InputError("when must be a datetime or ISO 8601 text, e.g. 2024-06-21T12:00:00Z, got '" +
                     when + "'");
  }
  if (!(latDeg >= -90.0 && latDeg <= 90.0) || !std::isfinite(lonDeg)) {
    throw InputError("lat must be in [-90, 90] and lon finite, got " + std::to_string(latDeg) +
                     ", " + std::to_string(lonDeg));
  }
  const SolarPosition sun = solarPosition(*utc, latDeg, lonDeg);
  return py::make_tuple(sun.azimuthDeg, sun.elevationDeg);
}

py::dict gridSpacingOf(const std::string& crs, const std::array<double, 6>& geoTransform, int width,
                       int height) {
  GridSpacing grid = gridSpacing(crs, geoTransform, width, height);
  py::dict out;
  out["x"] = grid.spacing.x;
  out["y"] = grid.spacing.y;
  out["rows"] = grid.spacing.rows.empty()
                    ? py::object(py::none())
                    : py::object(toNumpy(std::move(grid.spacing.rows), {height}));
  out["center"] =
      grid.spacing.center ? py::object(py::cast(*grid.spacing.center)) : py::object(py::none());
  out["z_unit"] = grid.zUnitFromCrs ? py::object(py::float_(grid.zUnitM)) : py::object(py::none());
  return out;
}

}  // namespace

}  // namespace aal::python

PYBIND11_MODULE(_aperture, m) {
  using namespace aal::python;
  m.doc() = "The compiled half of aperture (docs/python.md); use the functions of `aperture`.";
  m.attr("__version__") = aal::versionNumber();
  m.attr("software") = aal::softwareName();
  // The sun the tools default to (terrain/units.h), for aperture's defaults.
  m.attr("_DEFAULT_SUN_AZIMUTH_DEG") = aal::kDefaultSunAzimuthDeg;
  m.attr("_DEFAULT_SUN_ELEVATION_DEG") = aal::kDefaultSunElevationDeg;
  m.attr("_SUN_ANGULAR_RADIUS_DEG") = aal::kSunAngularRadiusDeg;

  // Bad input is a ValueError with the library's message, the one the
  // tools print before exiting with 2.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const aal::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<DemArray>(m, "_Dem", "A DEM for one call of _bake, _relief or _render.")
      .def(py::init(&makeDem), py::arg("z"), py::arg("voids"), py::arg("cell_x"), py::arg("cell_y"),
           py::arg("rows"), py::arg("center"), py::arg("z_scale"), py::arg("exaggeration"))
      .def_readonly("width", &DemArray::width)
      .def_readonly("height", &DemArray::height);

  m.def("_solar_position", &solarPositionOf, py::arg("when"), py::arg("lat"), py::arg("lon"),
        "The NOAA sun position (terrain/light/solar_position.h): (azimuth, elevation) in "
        "degrees. Use aperture.solar_position.");
  m.def("_grid_spacing", &gridSpacingOf, py::arg("crs"), py::arg("geotransform"), py::arg("width"),
        py::arg("height"),
        "The DEM reader's metric spacing of a placed grid: dict of x, y, rows, center, z_unit. "
        "Use aperture.metric_cell_size.");
  addBakeFunctions(m);
  addRenderFunction(m);
}
