#pragma once
// SWEEP_DIR/tables.md from results.csv's rows, in the shape of the paper's Tables 1–3 (ISNR §5.1): equal steps
// (steps, time, memory, MAPE, MSE per method), equal time (every method and the path tracer at each budget) and the
// residual at equal time and equal samples; and, for each trained model, its render time beside the path tracer's
// time to the same image error.
#include <string>
#include <vector>

#include "sweep/results_csv.hpp"

namespace clr::sweep {

std::string tables_markdown(const std::vector<Row>& rows, const std::string& title);

}  // namespace clr::sweep
