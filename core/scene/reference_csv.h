#pragma once
/// Reference data tables (assets/reference/*.csv): '#' comment lines, one header row, numeric rows.
#include <string>
#include <vector>

namespace ff::scene {

struct ReferenceTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;  ///< [column][row]
  /// The named column; throws std::runtime_error naming the file and the columns it has.
  const std::vector<double>& column(const std::string& name) const;
};

/// Reads a table; throws std::runtime_error with "file:line: ..." for unreadable or malformed input.
ReferenceTable read_reference_csv(const std::string& path);

}  // namespace ff::scene
