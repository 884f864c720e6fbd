// Samples from arrays and tables read from files, with their samples as NumPy arrays.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.h"
#include "brdffit/error.h"

namespace brdffit::python {

namespace {

// A read-only NumPy view of one field of every sample (`columns` doubles from `first`, one
// row per sample), keeping `owner` alive.
py::array sample_view(const PySamples& samples, const py::handle& owner, const double* first, size_t columns) {
  const size_t n = samples.set->size();
  static const double kNothing[3] = {0, 0, 0};
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(n)}, strides{static_cast<py::ssize_t>(sizeof(Sample))};
  if (columns > 1) shape.push_back(columns), strides.push_back(sizeof(double));
  py::array view(py::dtype::of<double>(), shape, strides, n ? first : kNothing, owner);
  view.attr("flags").attr("writeable") = false;
  return view;
}

const double* first_double(const Vec3& x) { return x.data(); }
const double* first_double(const double& x) { return &x; }

// The getter of a property viewing one field of every sample.
template <class Field>
auto sample_field(Field Sample::*field, size_t columns) {
  return [field, columns](const py::object& self) {
    const PySamples& samples = py::cast<const PySamples&>(self);
    const double* first = samples.set->empty() ? nullptr : first_double(samples.set->samples[0].*field);
    return sample_view(samples, self, first, columns);
  };
}

// The rows of an (N, 3) or (N,) array.
const double* rows_of(const DoubleArray& array, size_t n, size_t columns, const char* what) {
  const bool ok = columns == 1 ? array.ndim() == 1 && static_cast<size_t>(array.shape(0)) == n
                               : array.ndim() == 2 && static_cast<size_t>(array.shape(0)) == n && array.shape(1) == 3;
  if (!ok) fail("{}: expected shape ({}{}), as many rows as light", what, n, columns == 1 ? ",)" : ", 3)");
  return array.data();
}

PySamples samples_from_arrays(const DoubleArray& light, const DoubleArray& view, const DoubleArray& rgb,
                              const std::optional<DoubleArray>& weight, const std::string& source) {
  const std::vector<Vec3> ls = directions_from(light, "light"), vs = directions_from(view, "view");
  const size_t n = ls.size();
  if (light.ndim() != 2 || view.ndim() != 2 || vs.size() != n)
    fail("light and view: expected two (N, 3) arrays with the same N");
  const double* values = rows_of(rgb, n, 3, "rgb");
  const double* weights = weight ? rows_of(*weight, n, 1, "weight") : nullptr;
  auto set = std::make_shared<SampleSet>();
  set->source = source;
  set->weighting = weights ? "given" : "uniform";
  set->samples.resize(n);
  for (size_t i = 0; i < n; ++i) {
    Sample& s = set->samples[i];
    s.l = ls[i], s.v = vs[i];
    if (!(s.l.z() > 0.0 && s.v.z() > 0.0)) fail("{}: sample {}: a direction lies on or below the horizon", source, i);
    s.value = Rgb<double>(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
    if (!s.value.allFinite()) fail("{}: sample {}: the value is not finite", source, i);
    if ((s.value.array() < 0.0).any()) fail("{}: sample {}: negative reflectance", source, i);
    s.weight = weights ? weights[i] : 1.0;
    if (!std::isfinite(s.weight) || s.weight < 0.0)
      fail("{}: sample {}: the weight is negative or not finite", source, i);
  }
  if (n == 0) fail("{}: no samples", source);
  return {set};
}

bool is_csv(const std::string& path) { return path.size() >= 4 && path.compare(path.size() - 4, 4, ".csv") == 0; }

PyTable read_table(const py::handle& path_arg, double max_angle, size_t max_samples, uint64_t seed) {
  const std::string path = path_from(path_arg);
  if (!(max_angle >= 1.0 && max_angle <= 90.0)) fail("max_angle: {} is not in [1, 90] degrees", max_angle);
  const SamplingOptions options{max_angle, max_samples, seed};
  py::gil_scoped_release release;  // a MERL table takes a fraction of a second to read
  PyTable table;
  table.path = path;
  if (is_csv(path)) {
    table.set = std::make_shared<SampleSet>(load_samples(path, options));
  } else {
    table.table = open_measured(path);
    table.set = std::make_shared<SampleSet>(table.table->samples(options));
  }
  return table;
}

py::dict info_dict(const PyTable& table) {
  const TableInfo info = table.table ? table.table->describe() : describe_measured(table.path);
  const auto rgb = [](const Rgb<double>& c) { return py::make_tuple(c[0], c[1], c[2]); };
  py::dict d;
  d["format"] = info.format, d["resolution"] = info.resolution, d["valid"] = info.valid, d["invalid"] = info.invalid;
  d["min"] = rgb(info.min), d["max"] = rgb(info.max), d["albedo"] = rgb(info.albedo), d["zero"] = info.zero;
  py::list albedo_by_incidence;
  for (const TableInfo::AlbedoAt& a : info.albedo_by_incidence)
    albedo_by_incidence.append(py::make_tuple(a.theta_deg, rgb(a.albedo)));
  d["albedo_by_incidence"] = albedo_by_incidence;
  d["reciprocity"] = info.reciprocity, d["reciprocity_cosine_share"] = info.reciprocity_cosine_share;
  d["isotropic"] = info.isotropic, d["anisotropy"] = info.anisotropy, d["warnings"] = info.warnings;
  return d;
}

py::array lookup(const PyTable& table, const DoubleArray& light, const DoubleArray& view) {
  if (!table.table)
    fail("{}: a CSV of samples is not a table that can be evaluated at any pair of directions", table.path);
  const std::vector<Vec3> ls = directions_from(light, "light"), vs = directions_from(view, "view");
  if (ls.size() != vs.size()) fail("light and view: {} and {} directions (give as many of each)", ls.size(), vs.size());
  const MeasuredBrdf& measured = *table.table;
  return rows_of_three(ls.size(), light.ndim() == 1 && view.ndim() == 1, [&](size_t i, double* row) {
    const Rgb<double> f = measured.eval(ls[i], vs[i]);
    row[0] = f[0], row[1] = f[1], row[2] = f[2];
  });
}

}  // namespace

void bind_samples(py::module_& m) {
  py::class_<PySamples>(m, "Samples",
                        "Measured samples as the fitter sees them: directions, shaded values f·cosθi and\n"
                        "weights. The arrays are read-only views (no copy). Make them with brdffit.samples()\n"
                        "or brdffit.read().")
      .def_property_readonly("light", sample_field(&Sample::l, 3),
                             "(N, 3) unit directions towards the light, local frame (normal +z).")
      .def_property_readonly("view", sample_field(&Sample::v, 3), "(N, 3) unit directions towards the viewer.")
      .def_property_readonly(
          "rgb", sample_field(&Sample::value, 3),
          "(N, 3) measured shaded values f·cosθi per channel (what models' shaded values are compared with).")
      .def_property_readonly("weight", sample_field(&Sample::weight, 1),
                             "(N,) relative importance of each sample (e.g. the solid angle of a table bin).")
      .def_property_readonly(
          "source", [](const PySamples& s) { return s.set->source; }, "Where the samples came from.")
      .def_property_readonly(
          "weighting", [](const PySamples& s) { return s.set->weighting; },
          "How the weights were chosen (uniform, solid-angle, given, ...).")
      .def("__len__", [](const PySamples& s) { return s.set->size(); })
      .def("__repr__", [](const PySamples& s) {
        return fmt::format("<brdffit.Samples {} samples from {} ({} weights)>", s.set->size(), s.set->source,
                           s.set->weighting);
      });

  py::class_<PyTable, PySamples>(m, "Table",
                                 "A measured table read by brdffit.read(): its samples (see Samples) and, for\n"
                                 "MERL and RGL tables, look-ups of f at any pair of directions.")
      .def_readonly("path", &PyTable::path, "The file it was read from.")
      .def_property_readonly("info", &info_dict,
                             "What `brdffit info` prints: format, resolution, valid and invalid bins, min and\n"
                             "max of f, directional albedo at normal incidence (NaN for CSV).")
      .def("lookup", &lookup, py::arg("light"), py::arg("view"),
           "lookup(light, view) -> ndarray\n\n"
           "f(l, v) in 1/sr (not multiplied by cosθi) at (N, 3) or (3,) arrays of directions, as the\n"
           "table's reader interpolates it; zero below the horizon. Not available for CSV samples.")
      .def("__repr__", [](const PyTable& t) {
        return fmt::format("<brdffit.Table {}: {} samples ({} weights)>", t.path, t.set->size(), t.set->weighting);
      });

  m.def("read", &read_table, py::arg("path"), py::arg("max_angle") = 90.0, py::arg("max_samples") = 0,
        py::arg("seed") = 1,
        R"(read(path, max_angle=90, max_samples=0, seed=1) -> Table

Reads a MERL .binary, an RGL .bsdf or a CSV of samples (chosen by content, then extension),
and makes the samples a fit uses exactly as `brdffit fit` does with --max-angle (leave out
samples with θi or θo above it, degrees), --max-samples (a deterministic random subset; 0:
all) and --seed. Raises brdffit.Error naming the file and the problem.)");

  m.def("samples", &samples_from_arrays, py::arg("light"), py::arg("view"), py::arg("rgb"),
        py::arg("weight") = py::none(), py::arg("source") = "arrays",
        R"(samples(light, view, rgb, weight=None, source="arrays") -> Samples

Samples from arrays: light and view (N, 3) directions in the local frame (normal +z; made
unit length; both must lie above the horizon), rgb (N, 3) measured shaded values f·cosθi
(non-negative; the same quantity as Table.rgb and eval's shaded values), weight (N,)
non-negative importances (None: all 1). source names the set in messages and results.)");
}

}  // namespace brdffit::python
