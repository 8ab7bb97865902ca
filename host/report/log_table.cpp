#include "report/log_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "common/error.hpp"
#include "common/input_file.hpp"

namespace clr::report {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();  // getline drops a trailing empty field
  return fields;
}

}  // namespace

std::optional<std::size_t> LogTable::column(const std::string& name) const {
  const auto it = std::find(columns.begin(), columns.end(), name);
  if (it == columns.end()) return std::nullopt;
  return std::size_t(it - columns.begin());
}

LogTable read_log_table(const std::filesystem::path& path) { return read_csv_table(path, "step", "run's log"); }

LogTable read_csv_table(const std::filesystem::path& path, const std::string& required, const std::string& what) {
  std::istringstream in(read_input_text(path, what));
  std::string line;
  LogTable table;
  if (!std::getline(in, line) || line.empty())
    throw InputError(path.string() + ": no header line (not a " + what + ")");
  if (line.back() == '\r') line.pop_back();
  table.columns = split(line);
  if (!table.column(required))
    throw InputError(path.string() + ": the header has no '" + required + "' column (not a " + what +
                     "): " + clip(line));
  table.values.resize(table.columns.size());
  for (long number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const auto fields = split(line);
    const std::string where = path.string() + ":" + std::to_string(number) + ": ";
    if (fields.size() != table.columns.size())
      throw InputError(where + std::to_string(fields.size()) + " fields where the header names " +
                       std::to_string(table.columns.size()));
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = NAN;
      if (!fields[c].empty()) {
        char* end = nullptr;
        v = std::strtod(fields[c].c_str(), &end);
        if (end == fields[c].c_str() || *end != '\0')
          throw InputError(where + table.columns[c] + " '" + clip(fields[c]) + "' is not a number");
      }
      table.values[c].push_back(v);
    }
  }
  return table;
}

}  // namespace clr::report
