// Fits and scores from Python: brdffit.fit, brdffit.score and the result objects, whose fields
// are those of the result document `brdffit fit --out` writes.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <future>
#include <mutex>
#include <optional>

#include "bindings.h"
#include "brdffit/error.h"
#include "brdffit/io.h"
#include "brdffit/registry.h"
#include "brdffit/result_json.h"

namespace brdffit::python {

namespace {

// The results of one brdffit.fit call and what its document needs.
struct PyFitResults {
  std::vector<FitResult> results;
  std::shared_ptr<const SampleSet> data;
  std::string input_path;
  FitOptions options;

  nlohmann::json document() const { return fit_document_json(input_path, *data, options, results); }
};

// fit_models on a worker thread, without the GIL. Python runs its signal handlers only in the
// main thread, between bytecodes, so the main thread waits for the worker's events and runs them:
// after each solver iteration the worker hands over and waits, and the main thread calls
// `on_iteration` (if given) and checks for signals before letting it go on; during the grids, which
// have no iterations, it checks every 50 ms. A Ctrl-C (a handler that raises) or an exception
// from `on_iteration` sets FitOptions::cancel before the worker resumes, so the solver stops in
// that same iteration, and the exception propagates.
class InterruptibleFit {
 public:
  InterruptibleFit(const std::vector<const Model*>& models, const SampleSet& data, FitOptions options,
                   py::object on_iteration)
      : on_iteration_(std::move(on_iteration)) {
    options.cancel = &cancel_;
    options.on_iteration = [this](const std::string& model, int iteration) { hand_over(model, iteration); };
    fit_ = std::async(std::launch::async, [this, &models, &data, options] {
      struct Finished {  // tells the main thread however fit_models ends
        InterruptibleFit& fit;
        ~Finished() {
          const std::lock_guard<std::mutex> lock(fit.mutex_);
          fit.finished_ = true;
          fit.changed_.notify_all();
        }
      } finished{*this};
      return fit_models(models, data, options);
    });
  }

  std::vector<FitResult> results() {
    for (;;) {
      std::optional<Iteration> iteration;
      {
        py::gil_scoped_release release;
        std::unique_lock<std::mutex> lock(mutex_);
        changed_.wait_for(lock, std::chrono::milliseconds(50), [this] { return finished_ || waiting_; });
        if (finished_) break;
        iteration = waiting_;
      }
      try {
        if (iteration && !on_iteration_.is_none()) on_iteration_(iteration->model, iteration->number);
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      } catch (...) {
        stop();
        throw;
      }
      if (iteration) resume();
    }
    return fit_.get();
  }

 private:
  struct Iteration {
    std::string model;
    int number;
  };

  // In the worker: wait until the main thread has seen this iteration.
  void hand_over(const std::string& model, int number) {
    std::unique_lock<std::mutex> lock(mutex_);
    waiting_ = Iteration{model, number};
    changed_.notify_all();
    changed_.wait(lock, [this] { return !waiting_; });
  }

  void resume() {
    const std::lock_guard<std::mutex> lock(mutex_);
    waiting_.reset();
    changed_.notify_all();
  }

  // Cancels the fit and waits for the worker to end (with Cancelled, or its results, unused).
  void stop() {
    cancel_ = true;
    resume();
    py::gil_scoped_release release;
    fit_.wait();
    try {
      fit_.get();
    } catch (const std::exception&) {
    }
  }

  py::object on_iteration_;
  std::atomic<bool> cancel_{false};
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<Iteration> waiting_;
  bool finished_ = false;
  std::future<std::vector<FitResult>> fit_;
};

py::object to_python(const nlohmann::json& json) { return py::module_::import("json").attr("loads")(json_text(json)); }

// One value as a float, three as a tuple.
py::object value_or_tuple(const std::vector<double>& xs) {
  if (xs.size() == 1) return py::float_(xs[0]);
  return py::tuple(py::cast(xs));
}

// Every metric of kMetrics under its name (NaN kept: a float, where the document writes null).
py::dict metrics_dict(const Metrics& m) {
  py::dict d;
  for (const MetricInfo& info : kMetrics) d[info.name] = m.*info.value;
  return d;
}

// "{'cosine', 'log', ...}": the keys of metrics_dict, for the docstrings.
std::string metrics_keys_text() {
  std::string text;
  for (const MetricInfo& info : kMetrics) text += fmt::format("{}'{}'", text.empty() ? "{" : ", ", info.name);
  return text + "}";
}

// '"cosine", "log", "relative" or "l2"': what fit's metric= accepts, for its docstring.
std::string minimisable_metrics_choice() {
  std::vector<std::string> names;
  for (const MetricInfo& info : kMetrics)
    if (info.minimised) names.push_back(fmt::format("\"{}\"", info.name));
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

// A docstring built at import (from kMetrics), kept for as long as the module is loaded: pybind11
// keeps the pointer. @METRICS@ and @MINIMISABLE@ in `text` become the metrics' names.
const char* docstring(std::string text) {
  static std::deque<std::string> kept;
  for (const auto& [placeholder, names] : {std::pair<std::string, std::string>{"@METRICS@", metrics_keys_text()},
                                           {"@MINIMISABLE@", minimisable_metrics_choice()}})
    for (size_t at = text.find(placeholder); at != std::string::npos; at = text.find(placeholder, at + names.size()))
      text.replace(at, placeholder.size(), names);
  return kept.emplace_back(std::move(text)).c_str();
}

const PySamples& samples_of(const py::handle& data, py::object& holder) {
  holder = py::reinterpret_borrow<py::object>(data);
  if (py::isinstance<py::str>(data) || py::hasattr(data, "__fspath__"))
    holder = py::module_::import("brdffit").attr("read")(data);
  if (!py::isinstance<PySamples>(holder)) throw py::type_error("data: a Table, Samples or the path of a table");
  return py::cast<const PySamples&>(holder);
}

std::string input_path_of(const py::handle& holder, const PySamples& samples) {
  return py::isinstance<PyTable>(holder) ? py::cast<const PyTable&>(holder).path : samples.set->source;
}

std::vector<const Model*> models_from(const py::handle& models) {
  if (py::isinstance<py::str>(models)) return parse_model_list(py::cast<std::string>(models));
  std::vector<const Model*> list;
  for (const py::handle& m : models) list.push_back(&model_from(m));
  if (list.empty()) fail("models: no model given");
  return list;
}

PyFitResults fit(const py::handle& data, const py::handle& models, const std::string& metric, const std::string& loss,
                 double loss_scale, bool per_channel, bool converge, int threads, uint64_t seed,
                 const py::object& on_result, const py::object& on_iteration, const py::object& fix) {
  py::object holder;
  const PySamples& samples = samples_of(data, holder);
  PyFitResults out;
  out.data = samples.set;
  out.input_path = input_path_of(holder, samples);
  out.options.metric = metric_from_name(metric, "metric");
  out.options.loss = loss_from_name(loss, "loss");
  out.options.loss_scale = loss_scale;
  out.options.per_channel = per_channel;
  if (converge) out.options.polish_after = SIZE_MAX;  // as the CLI's --converge
  out.options.threads = threads;
  out.options.seed = seed;
  if (!fix.is_none())
    for (const auto& [name, value] : fix.cast<py::dict>())
      out.options.fixed.emplace_back(py::str(name).cast<std::string>(), value.cast<double>());
  const std::vector<const Model*> list = models_from(models);
  if (out.data->empty()) fail("{}: no samples left to fit (check --max-angle)", out.input_path);
  // One call of the library's fit_models, which shares work between the models (the Lambert
  // baseline, contained models' optima): the results are the CLI's.
  out.results = InterruptibleFit(list, *out.data, out.options, on_iteration).results();
  if (!on_result.is_none())
    for (const FitResult& result : out.results) on_result(result);
  return out;
}

py::dict score(const py::handle& data, const py::handle& model_arg, const py::handle& params) {
  py::object holder;
  const PySamples& samples = samples_of(data, holder);
  const bool from_fit = py::isinstance<FitResult>(model_arg);
  const Model& model =
      from_fit ? model_from(py::str(py::cast<const FitResult&>(model_arg).model)) : model_from(model_arg);
  const ModelValues values = values_from(model, from_fit && params.is_none() ? model_arg : params);
  if (samples.set->empty()) fail("{}: no samples left to score (check --max-angle)", input_path_of(holder, samples));
  const std::shared_ptr<const SampleSet> set = samples.set;
  Metrics metrics;
  {
    py::gil_scoped_release release;
    metrics = evaluate_metrics(model, values.values, *set, values.per_channel);
  }
  return metrics_dict(metrics);
}

const FitResult* best_of(const PyFitResults& r) { return best_result(r.results, r.options.metric); }

const FitResult& result_named(const PyFitResults& r, const std::string& name) {
  for (const FitResult& result : r.results)
    if (result.model == name) return result;
  throw py::key_error(fmt::format("no fit of model '{}' in these results", name));
}

}  // namespace

void bind_fit(py::module_& m) {
  py::class_<ParameterEstimate>(m, "ParameterEstimate", "A fitted parameter: value, standard deviation and flags.")
      .def_readonly("name", &ParameterEstimate::name, "The parameter's name.")
      .def_property_readonly(
          "value", [](const ParameterEstimate& p) { return value_or_tuple(p.value); },
          "The value: a float, or an (r, g, b) tuple for colours and per-channel fits.")
      .def_property_readonly(
          "stddev", [](const ParameterEstimate& p) { return value_or_tuple(p.stddev); },
          "Standard deviation(s) from the covariance at the optimum; NaN where not estimated\n"
          "(null in the JSON document).")
      .def_readonly("identifiable", &ParameterEstimate::identifiable, "False: the data do not determine it.")
      .def_readonly("at_bound", &ParameterEstimate::at_bound, "True: the optimum sits on a bound.")
      .def_readonly("fixed", &ParameterEstimate::fixed, "True: held at a given value (fit's fix=), not fitted.")
      .def("__repr__", [](const ParameterEstimate& p) {
        return fmt::format("{}={}", p.name, py::str(value_or_tuple(p.value)).cast<std::string>());
      });

  py::class_<FitResult>(m, "FitResult",
                        "One model's fit, with the fields of a model entry of the result document.\n"
                        "as_dict() gives that entry exactly as `brdffit fit --out` writes it.")
      .def_readonly("model", &FitResult::model, "The model's name.")
      .def_readonly("ok", &FitResult::ok, "True when the fit succeeded.")
      .def_property_readonly(
          "status", [](const FitResult& r) { return r.ok ? "ok" : "failed"; }, "'ok' or 'failed'.")
      .def_property_readonly(
          "verdict", [](const FitResult& r) { return verdict_name(r.verdict); },
          "'good', 'poor' (clearly worse than a Lambert baseline or leaving most of the data\n"
          "unexplained) or 'failed'.")
      .def_readonly("warnings", &FitResult::warnings, "One line each: what a user should know about this fit.")
      .def_property_readonly(
          "error", [](const FitResult& r) { return r.ok ? py::none() : py::object(py::str(r.error)); },
          "Why the fit failed, or None.")
      .def_property_readonly(
          "parameters",
          [](const FitResult& r) {
            py::dict d;
            for (const ParameterEstimate& p : r.parameters) d[py::str(p.name)] = py::cast(p);
            return d;
          },
          "{name: ParameterEstimate}, in the model's parameter order.")
      .def_property_readonly(
          "metrics", [](const FitResult& r) { return metrics_dict(r.metrics); },
          docstring(
              "@METRICS@: every error metric at the optimum\n(typical: the median relative error of a sample, see "
              "metric.h)."))
      .def_readonly("iterations", &FitResult::iterations, "Trust-region iterations over every stage.")
      .def_readonly("termination", &FitResult::termination, "How the last stage ended (Ceres' message).")
      .def_readonly("seconds", &FitResult::seconds, "Wall time of this model's fit.")
      .def_readonly("samples", &FitResult::samples, "Number of samples fitted.")
      .def_readonly("values", &FitResult::values, "The flattened values, in the model's order (eval accepts them).")
      .def_property_readonly(
          "channel_values",
          [](const FitResult& r) { return r.channel_values.empty() ? py::none() : py::cast(r.channel_values); },
          "With per_channel=True: one full value list per channel (r, g, b); otherwise None.")
      .def(
          "as_dict", [](const FitResult& r) { return to_python(fit_result_json(r)); },
          "as_dict() -> dict\n\nThis result as the result document's model entry (NaN written as None).")
      .def("__repr__", [](const FitResult& r) {
        if (!r.ok) return fmt::format("<brdffit.FitResult {} failed: {}>", r.model, r.error);
        std::string params;
        for (const ParameterEstimate& p : r.parameters)
          params += " " + p.name + "=" + py::str(value_or_tuple(p.value)).cast<std::string>();
        return fmt::format("<brdffit.FitResult {} ({}, cosine {:.4g}):{}>", r.model, verdict_name(r.verdict),
                           r.metrics.cosine, params);
      });

  py::class_<PyFitResults>(m, "FitResults",
                           "The fits of one brdffit.fit call, in the order the models were given: a sequence of\n"
                           "FitResult, also indexed by model name; document() is `brdffit fit --out`'s JSON.")
      .def("__len__", [](const PyFitResults& r) { return r.results.size(); })
      .def(
          "__getitem__",
          [](const PyFitResults& r, const py::object& key) -> const FitResult& {
            if (py::isinstance<py::str>(key)) return result_named(r, py::cast<std::string>(key));
            py::ssize_t i = py::cast<py::ssize_t>(key), n = static_cast<py::ssize_t>(r.results.size());
            if (i < 0) i += n;
            if (i < 0 || i >= n) throw py::index_error("fit result index out of range");
            return r.results[i];
          },
          py::return_value_policy::reference_internal)
      .def(
          "__iter__", [](const PyFitResults& r) { return py::make_iterator(r.results.begin(), r.results.end()); },
          py::keep_alive<0, 1>())
      .def_property_readonly(
          "best", [](const PyFitResults& r) { return best_of(r); }, py::return_value_policy::reference_internal,
          "The usable (good) fit with the lowest error in the minimised metric, or None: a poor fit is never best.")
      .def_property_readonly(
          "metric", [](const PyFitResults& r) { return metric_name(r.options.metric); },
          "The metric that was minimised.")
      .def_property_readonly(
          "samples", [](const PyFitResults& r) { return r.data->size(); }, "Samples fitted.")
      .def_property_readonly(
          "weighting", [](const PyFitResults& r) { return r.data->weighting; }, "Their weighting.")
      .def_property_readonly(
          "input", [](const PyFitResults& r) { return os_path(r.input_path); },
          "The table's path, or the samples' source (a name that is not UTF-8 decoded as os.fsdecode does).")
      .def(
          "document", [](const PyFitResults& r) { return to_python(r.document()); },
          "document() -> dict\n\nThe whole result document, as `brdffit fit --out` writes it.")
      .def(
          "save",
          [](const PyFitResults& r, const py::handle& path) {
            // The check every writer makes: never over the table the results came from.
            const std::string out = path_from(path);
            check_outputs({r.input_path}, {out});
            write_file_atomic(out, json_text(r.document(), 2) + "\n");
          },
          py::arg("path"),
          "save(path): writes the result document (JSON) whole or not at all, for brdffit report,\n"
          "render, compare and export.")
      .def("__repr__", [](const PyFitResults& r) {
        const FitResult* best = best_of(r);
        return fmt::format("<brdffit.FitResults {} models on {} ({} samples), best: {}>", r.results.size(),
                           printable(r.input_path), r.data->size(), best ? best->model : "none");
      });

  m.def("fit", &fit, py::arg("data"), py::arg("models") = "all", py::arg("metric") = "cosine", py::arg("loss") = "none",
        py::arg("loss_scale") = 0.0, py::arg("per_channel") = false, py::arg("converge") = false,
        py::arg("threads") = 0, py::arg("seed") = 1, py::arg("on_result") = py::none(),
        py::arg("on_iteration") = py::none(), py::arg("fix") = py::none(),
        docstring(R"(fit(data, models="all", metric="cosine", loss="none", loss_scale=0.0, per_channel=False,
    converge=False, threads=0, seed=1, on_result=None, on_iteration=None, fix=None) -> FitResults

Fits models to measured samples with the library's fitter, as `brdffit fit` does.

data         a Table (brdffit.read), Samples (brdffit.samples) or the path of a table.
models       "all", "lambert,ggx", or a list of names or Model objects.
metric       what is minimised: @MINIMISABLE@ (all are reported).
loss         robust loss per sample: "none", "huber" or "cauchy"; loss_scale where it bends
             (0: automatic).
per_channel  fit shape parameters per colour channel (colours always are).
converge     large tables: iterate to convergence on all samples instead of polishing.
threads      threads (0: every core). seed: the seed of the fitter's subsample.
on_result    None, or a callable given each model's FitResult in turn once the fit is done
             (an exception it raises propagates).
on_iteration None, or a callable given (model name, iteration) after each of the solver's
             iterations, while the fit waits (a progress display); an exception it raises
             stops the fit in that iteration and propagates.
fix          None, or {name: value} of parameters held at known values in every model that has
             them ({"metallic": 0} for a dielectric, {"ior": 1.5}): reported with fixed=True and
             no stddev; the other parameters' uncertainties take them as exact. A name no model
             has, or a value outside a model's bounds, raises brdffit.Error.

Returns FitResults: one FitResult per model (a model that fails to fit is reported with
status 'failed' and its error; the others are still fitted). Bad options or data raise
brdffit.Error with the command line's message.

The fit runs without the GIL (other Python threads go on). Ctrl-C stops it at the solver's
next iteration (during a grid search, when the grid ends): the call raises KeyboardInterrupt
and no result is kept.)"));

  m.def("score", &score, py::arg("data"), py::arg("model"), py::arg("params") = py::none(),
        docstring(R"(score(data, model, params=None) -> dict

Every error metric of given parameter values on samples, as `brdffit score` computes them:
@METRICS@. model is a name or Model with params as in
brdffit.eval (None: the defaults), or a FitResult (its own values, params left None).)"));
}

}  // namespace brdffit::python
