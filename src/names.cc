#include "brdffit/names.h"

#include <algorithm>
#include <cctype>

namespace brdffit {

std::string folded_name(const std::string& name) {
  const size_t first = name.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  std::string folded = name.substr(first, name.find_last_not_of(' ') - first + 1);
  for (char& c : folded) c = c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return folded;
}

namespace {

// Optimal string alignment distance: Levenshtein's edits plus the swap of two neighbours
// ("hlep" is one edit from "help"), each character edited at most once.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

size_t typo_edits(size_t length) { return length <= 4 ? 1 : length <= 8 ? 2 : 3; }

}  // namespace

std::string closest_name(const std::string& typed, const std::vector<std::string>& known) {
  const std::string folded = folded_name(typed);
  if (folded.empty()) return "";
  std::string best;
  size_t best_distance = typo_edits(folded.size()) + 1;
  for (const std::string& name : known) {
    const size_t distance = edit_distance(folded, folded_name(name));
    if (distance < best_distance) best = name, best_distance = distance;
  }
  return best;
}

std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known) {
  const std::string name = closest_name(typed, known);
  return name.empty() ? "" : "; did you mean '" + name + "'?";
}

}  // namespace brdffit
