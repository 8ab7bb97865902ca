#include "cli/number_checks.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace clr::cli {
namespace {

// The whole word must be a number; strtod's "nan", "inf" and overflow to ±HUGE_VAL all read as not finite.
bool parse_finite(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && errno != ERANGE && std::isfinite(out);
}

std::string range_text(double lo, double hi, bool lo_open) {
  std::ostringstream s;
  s << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
  return s.str();
}

}  // namespace

CLI::Validator finite_in(double lo, double hi, bool lo_open) {
  const std::string range = range_text(lo, hi, lo_open);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        if (!parse_finite(text, v)) return "value " + text + " is not a finite number";
        if (v > hi || v < lo || (lo_open && v == lo)) return "value " + text + " is not in " + range;
        return {};
      },
      "FLOAT in " + range);
}

CLI::Validator positive_finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (!parse_finite(text, v)) return "value " + text + " is not a finite number";
        return v > 0 ? std::string() : "value " + text + " is not > 0";
      },
      "FLOAT > 0");
}

CLI::Validator integer_at_least(long long lo) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        // strtoull would read "-1" as 2^64 - 1, so a minus sign goes through strtoll.
        const bool negative = text.find('-') != std::string::npos;
        char* end = nullptr;
        errno = 0;
        const long long v = negative ? std::strtoll(text.c_str(), &end, 10) : 0;
        const unsigned long long u = negative ? 0 : std::strtoull(text.c_str(), &end, 10);
        if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
          return "value " + text + " is not a whole number";
        const bool below = negative ? v < lo : (lo > 0 && u < static_cast<unsigned long long>(lo));
        return below ? "value " + text + " is less than " + std::to_string(lo) : std::string();
      },
      "INT >= " + std::to_string(lo));
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        return parse_finite(text, v) ? std::string() : "value " + text + " is not a finite number";
      },
      "FLOAT");
}

}  // namespace clr::cli
