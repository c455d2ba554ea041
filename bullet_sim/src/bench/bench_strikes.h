// bench --strikes: the strike matrix of issue 28 (tools/strike_matrix.h) over every shipped robot and the
// contact tests' look-alikes, as one JSON object.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace bullet_sim {

struct StrikeMatrixOptions {
  /// Every word must appear in a cell's name ("robot model 1ms 0.5m/s 30deg wall [coast]") for it to run.
  std::vector<std::string> filter;
  bool list_cells = false;  ///< every cell's figures, not only the summary and the failed cells
  std::string render_dir;  ///< "": no pictures; else a side and a chase view of each cell, at contact and end
  std::vector<double> steps = {0.001, 0.01};  ///< [s] the world step sizes the matrix runs at
};

/// Runs the matrix and reports: cells run and passed, the largest tilt, rise and energy gain, the RTF at each
/// step size, and each failed cell with its figures and bounds.
nlohmann::ordered_json strikeMatrixReport(const StrikeMatrixOptions& options);

}  // namespace bullet_sim
