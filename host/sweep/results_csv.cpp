#include "sweep/results_csv.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/enum_names.hpp"
#include "common/error.hpp"

namespace clr::sweep {
namespace {

// The columns of a results.csv written before incident_samples existed; a rerun reads it and writes today's.
constexpr const char* kOlderHeader =
    "kind,method,samples,seed,point,budget_minutes,steps,seconds,peak_device_mib,spp,render_seconds,mape,mse,"
    "relmse,non_finite,residual,residual_se,image,error_map";
constexpr std::size_t kOlderColumns = 19;
const std::string kHeader = std::string(kOlderHeader) + ",incident_samples";

std::string number(double v) {
  if (std::isnan(v)) return "";
  char s[32];
  std::snprintf(s, sizeof s, "%.9g", v);
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

constexpr EnumNames<RowKind, 2> kKinds = {{RowKind::Model, "model"}, {RowKind::PathTracing, "path_tracing"}};
constexpr EnumNames<Point, 3> kPoints = {
    {Point::Budget, "budget"}, {Point::Steps, "steps"}, {Point::Progress, "progress"}};

template <typename E, std::size_t N>
E parse_cell(const std::string& cell, const EnumNames<E, N>& names, const std::string& where, const char* column) {
  if (const auto value = value_named(cell, names)) return *value;
  throw InputError(where + ": unknown " + column + " '" + cell.substr(0, 64) + "' (" + choices(names) + ")");
}

}  // namespace

const char* to_string(RowKind kind) { return name_of(kind, kKinds); }
const char* to_string(Point point) { return name_of(point, kPoints); }

std::string Row::key() const {
  const std::string at = point == Point::Budget  ? number(budget_minutes)
                         : point == Point::Steps ? std::to_string(steps)
                                                 : std::to_string(spp);
  return std::string(to_string(kind)) + "/" + method + "/" + std::to_string(samples) + "/" + std::to_string(seed) +
         "/" + to_string(point) + "/" + at;
}

std::vector<Row> read_results(const std::filesystem::path& path) {
  std::vector<Row> rows;
  std::ifstream in(path);
  if (!in) return rows;
  std::string line;
  int line_number = 1;
  if (!std::getline(in, line) || (line != kHeader && line != kOlderHeader))
    throw InputError(path.string() + ":1: not a sweep's results.csv (header differs)");
  const std::size_t columns = line == kHeader ? kOlderColumns + 1 : kOlderColumns;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty()) continue;
    const auto c = split(line);
    const std::string where = path.string() + ":" + std::to_string(line_number);
    if (c.size() != columns) throw InputError(where + ": expected " + std::to_string(columns) + " cells");
    try {
      const auto real = [](const std::string& s) { return s.empty() ? kNone : std::stod(s); };
      Row r;
      r.kind = parse_cell(c[0], kKinds, where, "kind");
      r.method = c[1];
      r.samples = std::stoi(c[2]);
      r.seed = std::stoull(c[3]);
      r.point = parse_cell(c[4], kPoints, where, "point");
      r.budget_minutes = real(c[5]);
      r.steps = std::stoull(c[6]);
      r.seconds = std::stod(c[7]);
      r.peak_device_mib = real(c[8]);
      r.spp = std::stoi(c[9]);
      r.render_seconds = std::stod(c[10]);
      r.mape = real(c[11]);
      r.mse = real(c[12]);
      r.relmse = real(c[13]);
      r.non_finite = std::stoull(c[14]);
      r.residual = real(c[15]);
      r.residual_se = real(c[16]);
      r.image = c[17];
      r.error_map = c[18];
      if (columns > kOlderColumns && !c[19].empty()) r.incident_samples = std::stoull(c[19]);
      rows.push_back(r);
    } catch (const std::logic_error&) {  // std::stod and friends: invalid_argument, out_of_range
      throw InputError(where + ": malformed number");
    }
  }
  return rows;
}

void write_results(const std::filesystem::path& path, const std::vector<Row>& rows) {
  std::string text = kHeader + "\n";
  for (const auto& r : rows)
    text += std::string(to_string(r.kind)) + "," + r.method + "," + std::to_string(r.samples) + "," +
            std::to_string(r.seed) + "," + to_string(r.point) + "," + number(r.budget_minutes) + "," +
            std::to_string(r.steps) + "," + number(r.seconds) + "," + number(r.peak_device_mib) + "," +
            std::to_string(r.spp) + "," + number(r.render_seconds) + "," + number(r.mape) + "," + number(r.mse) + "," +
            number(r.relmse) + "," + std::to_string(r.non_finite) + "," + number(r.residual) + "," +
            number(r.residual_se) + "," + r.image + "," + r.error_map + "," +
            (r.incident_samples ? std::to_string(r.incident_samples) : "") + "\n";
  write_record_atomically(path, text, "sweep results");
}

}  // namespace clr::sweep
