// The names a user types (commands, models, metrics) against the names brdffit knows, for the
// "did you mean" of a usage error. Names are taken only as spelled: a model's name is what result
// documents, CSV columns and `render -m`/`export -m` match exactly, so a second spelling accepted
// in one place would fail in the next. The suggestion makes the one spelling easy to find.
#pragma once

#include <string>
#include <vector>

namespace brdffit {

// `name` as compared for suggestions: lower case, '_' read as '-', spaces at either end removed.
std::string folded_name(const std::string& name);

// The known name `typed` most likely meant: the first equal to it once folded, else the nearest by
// edit distance on folded names (insertions, deletions, substitutions and swaps of neighbours)
// when near enough to be a typo: 1 edit in a name of up to 4 characters, 2 up to 8, 3 beyond.
// "" when none is.
std::string closest_name(const std::string& typed, const std::vector<std::string>& known);

// "; did you mean 'ggx'?" to append to a message, or "" when no known name is close.
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known);

}  // namespace brdffit
