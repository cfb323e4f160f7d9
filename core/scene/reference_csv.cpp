#include "core/scene/reference_csv.h"

#include <sstream>
#include <stdexcept>

#include "core/frame/input_file.h"

namespace ff::scene {

const std::vector<double>& ReferenceTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return values[i];
  std::string have;
  for (const std::string& c : columns) have += (have.empty() ? "" : ", ") + c;
  throw std::runtime_error(path + ": no column '" + name + "' (columns: " + have + ")");
}

ReferenceTable read_reference_csv(const std::string& path) {
  std::string text, problem;
  if (!read_input_file(path, &text, kMaxTextInputBytes, kTextInputBound, &problem))
    throw std::runtime_error("reference table '" + path + "' " + problem);
  std::istringstream in(text);
  ReferenceTable t;
  t.path = path;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (t.columns.empty()) {
      t.columns = cells;
      t.values.resize(cells.size());
      continue;
    }
    if (cells.size() != t.columns.size())
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " + std::to_string(t.columns.size()) +
                               " values, got " + std::to_string(cells.size()));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      try {
        std::size_t used = 0;
        t.values[i].push_back(std::stod(cells[i], &used));
        if (used != cells[i].size()) throw std::invalid_argument("trailing text");
      } catch (const std::exception&) {
        throw std::runtime_error(path + ":" + std::to_string(line_no) + ": column '" + t.columns[i] +
                                 "': not a number: '" + cells[i] + "'");
      }
    }
  }
  if (t.columns.empty()) throw std::runtime_error(path + ": no header row");
  return t;
}

}  // namespace ff::scene
