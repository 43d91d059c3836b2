#pragma once
// Splits CSV text (no quoting, as our tools write it) into rows of cells; a trailing
// comma gives a last empty cell.

#include <sstream>
#include <string>
#include <vector>

namespace plantnbv {
namespace test {

inline std::vector<std::vector<std::string>> readCsv(const std::string& text)
{
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    rows.emplace_back();
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ','))
      rows.back().push_back(cell);
    if (!line.empty() && line.back() == ',')
      rows.back().push_back("");
  }
  return rows;
}

} // namespace test
} // namespace plantnbv
