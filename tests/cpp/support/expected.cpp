#include "support/expected.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

#include "support/models.h"

namespace isocam::test {
namespace {

const char* const kFile = "expected.txt";

struct Figure {
  std::string relation;  // =, <, <=, >, >=
  double value = 0, tolerance = 0;
  std::string reason;
  int line = 0;
};

struct Table {
  std::map<std::pair<std::string, std::string>, Figure> figures;
  std::string error;  // the first line that does not parse, if any
};

bool parse_number(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && std::isfinite(out);
}

// One entry: <case> <quantity> <relation> <value> [+- <tolerance>] # <reason>.
// Returns an empty string, or what is wrong with the line.
std::string parse_entry(const std::string& text, Figure& f, std::string& name,
                        std::string& quantity) {
  const std::size_t hash = text.find('#');
  if (hash == std::string::npos) return "no # reason";
  f.reason = text.substr(hash + 1);
  f.reason.erase(0, f.reason.find_first_not_of(" \t"));
  if (f.reason.empty()) return "empty reason after #";
  std::istringstream in(text.substr(0, hash));
  std::vector<std::string> t;
  for (std::string w; in >> w;) t.push_back(w);
  if (t.size() != 4 && t.size() != 6) return "want <case> <quantity> <relation> <value> [+- <tol>]";
  name = t[0];
  quantity = t[1];
  f.relation = t[2];
  if (f.relation != "=" && f.relation != "<" && f.relation != "<=" && f.relation != ">" &&
      f.relation != ">=")
    return "relation '" + f.relation + "' is none of = < <= > >=";
  if (!parse_number(t[3], f.value)) return "value '" + t[3] + "' is not a number";
  const bool equal = f.relation == "=";
  if (equal != (t.size() == 6)) return equal ? "= wants +- <tolerance>" : "a bound takes no +-";
  if (equal && (t[4] != "+-" || !parse_number(t[5], f.tolerance) || f.tolerance < 0))
    return "want +- <tolerance >= 0>";
  return "";
}

Table read_table() {
  Table table;
  const std::string path = data_path(kFile);
  std::ifstream in(path);
  if (!in) {
    table.error = "cannot read " + path;
    return table;
  }
  int n = 0;
  for (std::string text; std::getline(in, text);) {
    ++n;
    const std::size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    Figure f;
    f.line = n;
    std::string name, quantity, why = parse_entry(text, f, name, quantity);
    if (why.empty() && !table.figures.emplace(std::make_pair(name, quantity), f).second)
      why = "a second entry for " + name + " " + quantity;
    if (!why.empty()) {
      table.error = std::string(kFile) + ":" + std::to_string(n) + ": " + why;
      return table;
    }
  }
  return table;
}

bool holds(const Figure& f, double m) {
  if (f.relation == "=") return std::abs(m - f.value) <= f.tolerance;
  if (f.relation == "<") return m < f.value;
  if (f.relation == "<=") return m <= f.value;
  if (f.relation == ">") return m > f.value;
  return m >= f.value;
}

}  // namespace

::testing::AssertionResult meets_expected(const std::string& case_name, const std::string& quantity,
                                          double measured) {
  static const Table table = read_table();
  if (!table.error.empty()) return ::testing::AssertionFailure() << table.error;
  const auto it = table.figures.find({case_name, quantity});
  if (it == table.figures.end())
    return ::testing::AssertionFailure()
           << "no entry for " << case_name << " " << quantity << " in tests/data/" << kFile;
  const Figure& f = it->second;
  std::ostringstream want;
  want << f.relation << " " << f.value;
  if (f.relation == "=") want << " +- " << f.tolerance;
  const std::string where = std::string(kFile) + ":" + std::to_string(f.line);
  if (holds(f, measured)) {
    std::cout << "    figure " << case_name << " " << quantity << ": " << measured << " ("
              << want.str() << ", " << where << ")\n";
    return ::testing::AssertionSuccess();
  }
  // Six digits, as the figures are written (gtest's own stream prints 17).
  const double off = measured - f.value;
  std::ostringstream fail;
  fail << case_name << " " << quantity << ": measured " << measured << ", expected " << want.str()
       << " (" << where << "): off by " << off;
  if (f.value != 0) fail << " (" << 100 * off / std::abs(f.value) << " %)";
  fail << "; the entry's reason: " << f.reason;
  return ::testing::AssertionFailure() << fail.str();
}

}  // namespace isocam::test
