// The versioned result document shared by `fit`, `sphere` and `batch` (schema 1):
// {"schema": 1, "tool": "brdffit X.Y.Z", "input": {"path", "sha256"}, "samples", "weighting",
//  "metric", "models": [{"model", "status": "ok"|"failed", "error", "parameters":
//  {name: {"value", "stddev", "identifiable", "at_bound"}}, "metrics": {...}, "iterations",
//  "termination", "seconds"}]}
// Colours (and per-channel shape parameters) have [r,g,b] values and stddevs; NaN stddevs are null.
// Also what every reader of results shares: finding a model's result, the best one, a
// material's name, values as text.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "brdffit/fit.h"

namespace brdffit {

// A 3-vector, a direction or an RGB colour (the same type), as a JSON array [x, y, z].
inline nlohmann::json json_array(const Vec3& v) { return {v[0], v[1], v[2]}; }

// The deepest nesting of arrays and objects in any JSON file brdffit reads (its own documents
// nest five deep, glTF files a few more).
constexpr size_t kMaxJsonDepth = 64;

// How deeply `text`'s arrays and objects nest (brackets outside strings), counted without
// parsing: linear and without recursion.
size_t json_depth(const std::string& text);

// Throws Error naming `path` when `text` nests deeper than kMaxJsonDepth.
void check_json_depth(const std::string& text, const std::string& path, const std::string& what);

// Every JSON file brdffit reads goes through here: the file parsed, after its depth was checked
// against kMaxJsonDepth. Throws Error naming the file and saying it is not a `what` ("glTF
// file") when it cannot be read, nests too deeply or is not JSON.
nlohmann::json read_json_file(const std::string& path, const std::string& what);

// The value at keys... inside `j` (e.g. {"input", "sha256"}), or nullptr when a key is missing
// or a value on the way is not an object: optional fields looked up without operator[] on a
// const value (undefined behaviour when the key is missing).
const nlohmann::json* json_field(const nlohmann::json& j, std::initializer_list<const char*> keys);

// Every JSON text brdffit writes or prints: a string that is not UTF-8 (a message quoting a
// file name that is not) has its bad bytes replaced by U+FFFD instead of failing the write.
// Names that must come back exactly are stored with put_name.
std::string json_text(const nlohmann::json& j, int indent = -1);

// A name (a path, a file or material name: bytes, not necessarily UTF-8) under `key` of
// `object`: as it is when it is UTF-8; otherwise with its bad bytes replaced, for people and
// other readers, and losslessly as hex under key + "_bytes", which get_name prefers.
void put_name(nlohmann::json& object, const std::string& key, const std::string& name);
// The name put_name stored, or nullopt when `object` has no string under `key`. Throws Error
// starting with `where` when key + "_bytes" is there but not hex.
std::optional<std::string> get_name(const nlohmann::json& object, const std::string& key, const std::string& where);

// JSON has no NaN: a number that is not finite is written as null.
nlohmann::json number_or_null(double x);

// One value as it is, several as [a,b,c], each with `format` (a fmt format such as "{:.4g}").
std::string format_values(const std::vector<double>& xs, const char* format = "{:.4g}");

// The result of `model` among `results`, or nullptr.
const FitResult* find_result(const std::vector<FitResult>& results, const std::string& model);

// The result with the lowest error under `metric` among the usable fits (verdict good, finite
// error), or nullptr when none is usable: a poor fit is never called best, whatever its error.
const FitResult* best_result(const std::vector<FitResult>& results, Metric metric);

// How many of `results` fitted but were judged poor.
int count_poor(const std::vector<FitResult>& results);

// Every metric of kMetrics under its name, not finite ones as null ("metrics" of a model entry,
// `brdffit score --json`).
nlohmann::json metrics_json(const Metrics& metrics);
// The metrics metrics_json wrote; a metric that is missing or null reads as NaN (documents
// written before it existed lack it), as every metric of what is not an object.
Metrics metrics_from_json(const nlohmann::json& j);

nlohmann::json fit_result_json(const FitResult& result);

// The whole document for one input; callers may add keys (e.g. the sphere pipeline's).
nlohmann::json fit_document_json(const std::string& input_path, const SampleSet& data, const FitOptions& options,
                                 const std::vector<FitResult>& results);

// Reads back a document written by fit_document_json; throws Error naming the file when it is
// not one. Used by compare, report, render and export.
struct FitDocument {
  std::string path;
  nlohmann::json json;
  std::string input_path;
  std::vector<FitResult> results;
};
FitDocument read_fit_document(const std::string& path);

// The result documents a batch summary (summary.json, batch_summary_json) lists: those of the
// materials that were fitted, absolute (relative ones resolved against the summary's folder).
// Empty when the file is not a batch summary (not JSON, or no "materials" array). Throws Error
// naming the file and field when a material entry is malformed.
std::vector<std::string> read_summary_results(const std::string& path);

// The documents `inputs` name, for compare and report: result documents named directly, those a
// batch's summary.json lists, or every *.json in a folder but the batch's summary.json (sorted).
// Each file once, however it is spelled. Throws Error naming the input that names none.
std::vector<FitDocument> read_fit_documents(const std::vector<std::string>& inputs);

// The files the documents were read from.
std::vector<std::string> document_paths(const std::vector<FitDocument>& documents);

// `brdffit fit --csv`: one row per model: status, verdict, every metric of kMetrics, iterations
// and seconds, then for every parameter of any model (first appearance order) one column per
// component (NAME, or NAME_r, NAME_g, NAME_b: a parameter that is a colour in one model and a
// scalar in another has both), its stddevs (NAME_stddev...) and three flags, NAME_at_bound,
// NAME_identifiable and NAME_fixed (held by --fix) (1 or 0). A model without that parameter
// leaves its cells empty; an unknown stddev is empty too.
std::string fit_results_csv(const std::vector<FitResult>& results);

// What a document's material is called: the batch's name for it ("material"), else the name of
// the table it was fitted to (table_material_name).
std::string material_name(const FitDocument& document);

}  // namespace brdffit
