#pragma once
// Range checks for numeric options. CLI11's own Range lets NaN through (every comparison with NaN is false) and
// accepts "inf"; these reject both, so that an impossible value exits 2 with CLI11's one line naming the option
// (docs/design.md §4) instead of running with it.
#include <CLI/CLI.hpp>

namespace clr::cli {

// A finite number in [lo, hi]; with `lo_open`, in (lo, hi] (e.g. a learning rate must be > 0).
CLI::Validator finite_in(double lo, double hi, bool lo_open = false);

// A finite number > 0 (a time budget).
CLI::Validator positive_finite();

// A whole number ≥ lo (seeds, step counts); the option's type still bounds it from above.
CLI::Validator integer_at_least(long long lo);

// A finite number, any sign (coordinates).
CLI::Validator finite_number();

}  // namespace clr::cli
