#pragma once
// log.csv as the report reads it: columns by name, so that a log written before a column existed (no `samples`, no
// evaluations) or after new ones were added still reads; a column the log lacks is simply absent.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace clr::report {

struct LogTable {
  std::vector<std::string> columns;         // the header's names, in the file's order
  std::vector<std::vector<double>> values;  // one vector per column, a value per row; NaN where a field is empty

  std::size_t rows() const { return values.empty() ? 0 : values.front().size(); }
  // The column named `name`, or nullopt where the log lacks it.
  std::optional<std::size_t> column(const std::string& name) const;
};

// Reads `path` (a run's log.csv). InputError "PATH:LINE: …" naming the line and field at fault when a row has
// another field count than the header or a field that is neither empty, a number nor nan; and "PATH: …" when the
// file has no header or lacks the `step` column every run's log starts with.
LogTable read_log_table(const std::filesystem::path& path);
// The same for any numeric CSV file with a header (a path tracer's points.csv): `required` names the column the
// file must have, `what` what it is for the message.
LogTable read_csv_table(const std::filesystem::path& path, const std::string& required, const std::string& what);

}  // namespace clr::report
