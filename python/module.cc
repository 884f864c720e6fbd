// The Python module `brdffit`: the model library and its evaluation (this file), samples and
// tables (samples.cc), fits and scores (fitting.cc). Usage: docs/library.md, "Python".
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.h"
#include "brdffit/error.h"
#include "brdffit/registry.h"

namespace brdffit::python {

namespace {

std::string shape_text(const py::array& array) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    text += (d ? ", " : "") + std::to_string(array.shape(d)) + (array.ndim() == 1 ? "," : "");
  return text + ")";
}

// "name=x" or "name=r,g,b" for parameter_values, each double in its shortest exact form.
std::string assignment(const std::string& name, const std::vector<double>& numbers) {
  std::string text = name + "=";
  for (size_t i = 0; i < numbers.size(); ++i) text += fmt::format("{}{}", i ? "," : "", numbers[i]);
  return text;
}

std::vector<double> numbers_of(const py::handle& value) {
  if (py::isinstance<py::str>(value)) throw py::type_error("parameter values are numbers or (r, g, b) sequences");
  if (py::isinstance<py::sequence>(value) || py::isinstance<py::array>(value))
    return py::cast<std::vector<double>>(value);
  return {py::cast<double>(value)};
}

std::string parameter_list(const Model& model) {
  std::string names;
  for (const ParamSpec& p : model.parameters()) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

std::string param_repr(const ParamSpec& p) {
  return fmt::format("Parameter('{}', {}[{:g}, {:g}], default {:g}: {})", p.name,
                     p.channels == 3 ? "rgb " : (p.integer ? "int " : ""), p.lower, p.upper, p.default_value,
                     p.meaning);
}

py::tuple eval_model(const py::handle& model_arg, const py::handle& params, const DoubleArray& light,
                     const DoubleArray& view) {
  const Model& model = model_from(model_arg);
  const ModelValues values = values_from(model, params);
  const std::vector<Vec3> ls = directions_from(light, "light"), vs = directions_from(view, "view");
  if (ls.size() != vs.size() && ls.size() != 1 && vs.size() != 1)
    fail("light and view: {} and {} directions (give as many of each, or one of either)", ls.size(), vs.size());
  const size_t n = std::max(ls.size(), vs.size());
  const bool single = light.ndim() == 1 && view.ndim() == 1;
  const auto l_of = [&](size_t i) -> const Vec3& { return ls[ls.size() == 1 ? 0 : i]; };
  const auto v_of = [&](size_t i) -> const Vec3& { return vs[vs.size() == 1 ? 0 : i]; };
  const auto store = [](const Rgb<double>& rgb, double* row) { row[0] = rgb[0], row[1] = rgb[1], row[2] = rgb[2]; };

  py::array_t<double> shaded = rows_of_three(n, single, [&](size_t i, double* row) {
    store(shade_fitted(model, values.values, values.per_channel, l_of(i), v_of(i)), row);
  });
  if (!model.has_brdf()) return py::make_tuple(shaded, py::none());
  py::array_t<double> f = rows_of_three(n, single, [&](size_t i, double* row) {
    if (values.per_channel.empty()) return store(*model.brdf(values.values.data(), l_of(i), v_of(i)), row);
    for (int c = 0; c < 3; ++c) row[c] = (*model.brdf(values.per_channel[c].data(), l_of(i), v_of(i)))[c];
  });
  return py::make_tuple(shaded, f);
}

}  // namespace

const Model& model_from(const py::handle& model) {
  if (py::isinstance<Model>(model)) return py::cast<const Model&>(model);
  const std::string name = py::cast<std::string>(model);
  const Model* found = find_model(name);
  if (found) return *found;
  // The command line's message for an unknown name, with its suggestion (parse_model_list throws it).
  if (name.find(',') == std::string::npos) parse_model_list(name);
  fail("'{}' is not one model (known: {})", name, model_names());
}

ModelValues values_from(const Model& model, const py::handle& params) {
  if (params.is_none()) return {model.default_values(), {}};
  if (py::isinstance<FitResult>(params)) {
    const FitResult& fit = py::cast<const FitResult&>(params);
    if (fit.model != model.name()) fail("params: a fit of {}, not of {}", fit.model, model.name());
    if (!fit.ok) fail("params: the {} fit failed ({})", fit.model, fit.error);
    return {fit.values, fit.channel_values};
  }
  std::vector<std::string> assignments;
  if (py::isinstance<py::dict>(params)) {
    for (const auto& [name, value] : py::cast<py::dict>(params))
      assignments.push_back(assignment(py::cast<std::string>(name), numbers_of(value)));
  } else if (py::isinstance<py::sequence>(params) || py::isinstance<py::array>(params)) {
    const std::vector<double> flat = numbers_of(params);
    if (static_cast<int>(flat.size()) != model.num_values())
      fail("params: {} values given, model {} has {} ({}; colours take 3)", flat.size(), model.name(),
           model.num_values(), parameter_list(model));
    for (const ParamSpec& p : model.parameters()) {
      const auto first = flat.begin() + model.offset_of(p.name);
      assignments.push_back(assignment(p.name, std::vector<double>(first, first + p.channels)));
    }
  } else {
    throw py::type_error("params: None, a dict {name: value}, a sequence of every value or a FitResult");
  }
  return {parameter_values(model, assignments), {}};
}

std::string path_from(const py::handle& path) {
  // A name's bytes, as the file system holds them: os.fsencode undoes what os.fsdecode (and so
  // os.listdir) made of a name that is not UTF-8.
  return py::cast<std::string>(py::module_::import("os").attr("fsencode")(path));
}

py::object os_path(const std::string& path) { return py::module_::import("os").attr("fsdecode")(py::bytes(path)); }

std::vector<Vec3> directions_from(const DoubleArray& array, const char* what) {
  const bool single = array.ndim() == 1 && array.shape(0) == 3;
  if (!single && !(array.ndim() == 2 && array.shape(1) == 3))
    fail("{}: expected an (N, 3) array of directions or one direction of shape (3,), got shape {}", what,
         shape_text(array));
  const size_t n = single ? 1 : array.shape(0);
  const double* xyz = array.data();
  std::vector<Vec3> directions(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec3 d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
    if (!d.allFinite()) fail("{}: direction {} is not finite", what, i);
    directions[i] = normalized_or_zero(d);
    if (directions[i].isZero()) fail("{}: direction {} is the zero vector", what, i);
  }
  return directions;
}

void bind_models(py::module_& m) {
  py::class_<ParamSpec>(m, "Parameter", "One parameter of a model: its name, bounds, default and meaning.")
      .def_readonly("name", &ParamSpec::name, "The name, as in --param NAME=VALUE and in result documents.")
      .def_readonly("channels", &ParamSpec::channels, "3 for colours (r, g, b), 1 for shape parameters.")
      .def_readonly("lower", &ParamSpec::lower, "Lowest allowed value.")
      .def_readonly("upper", &ParamSpec::upper, "Highest allowed value.")
      .def_readonly("default", &ParamSpec::default_value, "Value used when none is given.")
      .def_readonly("meaning", &ParamSpec::meaning, "One line: what the parameter does.")
      .def_property_readonly(
          "role", [](const ParamSpec& p) { return role_name(p.role); },
          "What kind of parameter it is (diffuse_colour, roughness, ...).")
      .def_readonly("integer", &ParamSpec::integer, "True when only integer values are allowed.")
      .def("__repr__", &param_repr);

  py::class_<Model>(m, "Model",
                    "A reflectance model of the library (see brdffit.models()). Models predict the shaded\n"
                    "value f(l,v)·max(n·l,0) in the local frame whose normal is n = (0, 0, 1).")
      .def_property_readonly("name", &Model::name, "The model's name, as the command line spells it.")
      .def_property_readonly("summary", &Model::summary, "One line: the formula and its source.")
      .def_property_readonly("parameters", &Model::parameters, "The parameters (list of Parameter), in order.")
      .def_property_readonly("has_brdf", &Model::has_brdf,
                             "True for physically based models: f exists (and eval returns it).")
      .def_property_readonly("energy_conserving", &Model::energy_conserving,
                             "True when the directional albedo stays at most 1 within the bounds.")
      .def_property_readonly("num_values", &Model::num_values,
                             "Length of the flattened value vector (colours take 3 values).")
      .def("default_values", &Model::default_values,
           "default_values() -> list[float]\n\nThe flattened default values, in parameter order.")
      .def("__repr__",
           [](const Model& model) { return fmt::format("<brdffit.Model {}: {}>", model.name(), model.summary()); });

  m.def(
      "models",
      [] {
        std::vector<const Model*> list;
        for (const auto& model : all_models()) list.push_back(model.get());
        return list;
      },
      py::return_value_policy::reference,
      "models() -> list[Model]\n\n"
      "Every model brdffit knows, in the command line's order, with its parameters (names,\n"
      "bounds, defaults, meanings).");
  m.def("model", &model_from, py::arg("name"), py::return_value_policy::reference,
        "model(name) -> Model\n\nThe model with this name; brdffit.Error names the known ones otherwise.");

  m.def("eval", &eval_model, py::arg("model"), py::arg("params"), py::arg("light"), py::arg("view"),
        R"(eval(model, params, light, view) -> (shaded, f)

Evaluates a model at many pairs of directions at once.

model   a name ("ggx") or a Model.
params  None (the defaults); a dict {name: value}, colours as one value or (r, g, b), the
        others at their defaults; a sequence of all model.num_values flattened values; or a
        FitResult of this model (its per-channel values too). Values are checked as
        `brdffit eval --param` checks them, with the same messages.
light, view
        unit or non-unit directions in the local frame (normal +z): arrays of shape (N, 3),
        or (3,) for one direction; one of them may be a single direction for all N.

Returns two float64 arrays of shape (N, 3) ((3,) when both inputs are single directions):
the shaded values f(l,v)·max(n·l,0) per channel, and f itself (1/sr), or None for models
without a BRDF (stylised shaders). Runs on every core without holding the GIL.)");
}

}  // namespace brdffit::python

PYBIND11_MODULE(brdffit, m) {
  namespace bp = brdffit::python;
  m.doc() = R"(brdffit: fit analytic BRDF models to measured reflectance, from Python.

The same library as the `brdffit` command line. Conventions: directions are in the local
frame whose normal is n = (0, 0, 1); a model's shaded value is f(l,v)·max(n·l,0); measured
samples hold f·cosθi per colour channel (r, g, b).

    models(), model(name)         the model library and its parameters
    eval(model, params, l, v)     shaded values and f at arrays of directions
    read(path)                    a MERL .binary, RGL .bsdf or CSV table -> Table
    samples(light, view, rgb)     samples from arrays -> Samples
    fit(data, models=...)         fit models -> FitResults (the fields of `brdffit fit --out`)
    score(data, model, params)    every error metric of given parameters

Problems with input or options raise brdffit.Error (a ValueError) with the command line's
message.)";
  m.attr("__version__") = BRDFFIT_VERSION;
  // Every docstring starts with its own Python signature (pybind11's would show C++ types).
  pybind11::options options;
  options.disable_function_signatures();
  pybind11::register_exception<brdffit::Error>(m, "Error", PyExc_ValueError).attr("__doc__") =
      "Bad input or options: the message names the file or argument and the problem, as the CLI's does.";
  bp::bind_models(m);
  bp::bind_samples(m);
  bp::bind_fit(m);
}
