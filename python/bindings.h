// Shared pieces of the Python module `brdffit` (pybind11): argument conversion and the parts
// each binding file registers. The module only converts between Python and the library; every
// computation is the library's.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "brdffit/fit.h"
#include "brdffit/measured.h"
#include "brdffit/model.h"
#include "brdffit/parallel.h"
#include "brdffit/samples.h"

namespace brdffit::python {

namespace py = pybind11;

// Any array-like of float64, converted to a C-contiguous array when it is not one already.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The samples behind a Python `Samples` object (and its subclass `Table`), shared so that
// NumPy views of them and fits running without the GIL keep them alive.
struct PySamples {
  std::shared_ptr<const SampleSet> set;
};

// A table read from a file: its samples and, for MERL and RGL tables (not CSV), the table
// itself for look-ups at any pair of directions.
struct PyTable : PySamples {
  std::string path;
  std::shared_ptr<const MeasuredBrdf> table;  // nullptr for a CSV of samples
};

// Parameter values to evaluate a model with: one flattened vector, or (for a fit made with
// per_channel=True) one vector per colour channel.
struct ModelValues {
  std::vector<double> values;
  std::vector<std::vector<double>> per_channel;
};

// A model given by name or as a brdffit.Model; throws brdffit::Error (the CLI's message) for
// an unknown name.
const Model& model_from(const py::handle& model);

// Values from None (the defaults), a dict {name: value or (r, g, b)}, a flat sequence of
// model.num_values numbers, or a FitResult of this model. Dicts and sequences are checked as
// the CLI checks --param (same messages).
ModelValues values_from(const Model& model, const py::handle& params);

// A str or os.PathLike (pathlib.Path) as a path.
std::string path_from(const py::handle& path);
// A path brdffit holds (bytes) as Python gives names: os.fsdecode, so any name round-trips.
py::object os_path(const std::string& path);

// Unit directions from an (N, 3) or (3,) array; `what` names the argument in messages.
// Throws Error for a wrong shape, a non-finite component or a zero vector.
std::vector<Vec3> directions_from(const DoubleArray& array, const char* what);

// An (N, 3) float64 array (or (3,) when `single`), filled by fill(i, row pointer) for every
// row i without the GIL, on every core. fill must not throw.
template <class Fill>
py::array_t<double> rows_of_three(size_t n, bool single, Fill&& fill) {
  py::array_t<double> out = single ? py::array_t<double>({size_t{3}}) : py::array_t<double>({n, size_t{3}});
  double* rows = out.mutable_data();
  {
    py::gil_scoped_release release;
    const size_t chunk = 16384;
    parallel_for((n + chunk - 1) / chunk, thread_count(0), [&](size_t c) {
      for (size_t i = c * chunk; i < std::min(n, (c + 1) * chunk); ++i) fill(i, rows + 3 * i);
    });
  }
  return out;
}

void bind_models(py::module_& m);
void bind_samples(py::module_& m);
void bind_fit(py::module_& m);

}  // namespace brdffit::python
