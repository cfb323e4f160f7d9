#include <algorithm>

#include "core/scene/schema.h"
#include "core/scene/schema_text.h"

namespace ff::scene {

std::string Issue::to_string() const {
  std::string out = file;
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
    if (column > 0) {
      out += ':';
      out += std::to_string(column);
    }
  }
  out += ": ";
  if (!key.empty()) out += "key '" + key + "': ";
  return out + message;
}

namespace {
std::string all_issues(const std::vector<Issue>& issues) {
  std::string out;
  for (std::size_t i = 0; i < issues.size(); ++i) {
    if (i) out += '\n';
    out += issues[i].to_string();
  }
  return out;
}
}  // namespace

SceneError::SceneError(std::vector<Issue> list)
    : std::runtime_error(all_issues(list)), issues(std::move(list)) {}

// ---- Document -------------------------------------------------------------------------------

namespace {
const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Number: return "number";
    case Kind::Integer: return "integer";
    case Kind::Boolean: return "boolean";
    case Kind::String: return "string";
    case Kind::Choice: return "choice";
    case Kind::NumberList: return "number_list";
    case Kind::StringList: return "string_list";
  }
  return "?";
}
}  // namespace

const Document::Entry& Document::entry(const std::string& path, std::initializer_list<Kind> kinds,
                                       const char* accessor) const {
  auto it = entries_.find(path);
  if (it == entries_.end())
    throw std::logic_error("scene: '" + path + "' is not a declared key (Document::" + accessor + ")");
  const Entry& e = it->second;
  if (!e.array.empty())
    throw std::logic_error("scene: '" + path + "' is a key of the array of tables [[" + e.array +
                           "]]; read it with Document::" + accessor + "(path, index)");
  if (kinds.size() && std::find(kinds.begin(), kinds.end(), e.kind) == kinds.end())
    throw std::logic_error("scene: '" + path + "' is declared as " + kind_name(e.kind) +
                           ", not readable with Document::" + accessor);
  if (kinds.size() && std::holds_alternative<std::monostate>(e.value))
    throw std::logic_error("scene: '" + path +
                           "' has no value: its table is absent (check table_present first)");
  return e;
}

double Document::number(const std::string& path) const {
  return std::get<double>(entry(path, {Kind::Number}, "number").value);
}

long long Document::integer(const std::string& path) const {
  return std::get<long long>(entry(path, {Kind::Integer}, "integer").value);
}

bool Document::boolean(const std::string& path) const {
  return std::get<bool>(entry(path, {Kind::Boolean}, "boolean").value);
}

const std::string& Document::string(const std::string& path) const {
  return std::get<std::string>(entry(path, {Kind::String, Kind::Choice}, "string").value);
}

std::vector<double> Document::numbers(const std::string& path) const {
  return std::get<std::vector<double>>(entry(path, {Kind::NumberList}, "numbers").value);
}

std::vector<std::string> Document::strings(const std::string& path) const {
  return std::get<std::vector<std::string>>(entry(path, {Kind::StringList}, "strings").value);
}

bool Document::present(const std::string& path) const {
  return entry(path, {}, "present").present;
}

bool Document::table_present(const std::string& path) const {
  if (arrays_.count(path))
    throw std::logic_error("scene: '" + path +
                           "' is an array of tables (Document::table_present); use Document::count");
  auto it = tables_.find(path);
  if (it == tables_.end())
    throw std::logic_error("scene: '" + path + "' is not a declared table (Document::table_present)");
  return it->second;
}

std::string Document::where(const std::string& path) const {
  return entry(path, {}, "where").where;
}

Issue Document::issue(const std::string& path, std::string message) const {
  const Entry& e = entry(path, {}, "issue");
  if (!e.present) return Issue{file_name_, 0, 0, path, std::move(message)};
  return Issue{e.file, e.line, e.column, path, std::move(message)};
}

std::string Document::value_text(const std::string& path) const {
  return text::toml_value(entry(path, {}, "value_text").value);
}

// ---- arrays of tables -----------------------------------------------------------------------

std::size_t Document::count(const std::string& array_path) const {
  auto it = arrays_.find(array_path);
  if (it == arrays_.end())
    throw std::logic_error("scene: '" + array_path + "' is not a declared array of tables" +
                           (tables_.count(array_path) ? " but a plain table" : "") +
                           " (Document::count)");
  return it->second.elements.size();
}

const Document::Element& Document::element(const std::string& path, std::size_t index,
                                           const char* accessor) const {
  auto it = entries_.find(path);
  if (it == entries_.end())
    throw std::logic_error("scene: '" + path + "' is not a declared key (Document::" + accessor + ")");
  const std::string& array = it->second.array;
  if (array.empty())
    throw std::logic_error("scene: '" + path + "' is not a key of an array of tables; read it with Document::" +
                           accessor + "(path)");
  const auto& elements = arrays_.at(array).elements;
  if (index >= elements.size())
    throw std::logic_error("scene: index " + std::to_string(index) + " is out of range for [[" + array +
                           "]], which has " + std::to_string(elements.size()) + " element" +
                           (elements.size() == 1 ? "" : "s") + " (Document::" + accessor + ")");
  return elements[index];
}

const Document::Entry& Document::entry(const std::string& path, std::size_t index,
                                       std::initializer_list<Kind> kinds, const char* accessor) const {
  const Element& el = element(path, index, accessor);
  const Entry& e = el.entries.at(path);
  if (kinds.size() && std::find(kinds.begin(), kinds.end(), e.kind) == kinds.end())
    throw std::logic_error("scene: '" + path + "' is declared as " + kind_name(e.kind) +
                           ", not readable with Document::" + accessor);
  if (kinds.size() && std::holds_alternative<std::monostate>(e.value))
    throw std::logic_error("scene: '" + path + "' has no value in element " + std::to_string(index));
  return e;
}

double Document::number(const std::string& path, std::size_t index) const {
  return std::get<double>(entry(path, index, {Kind::Number}, "number").value);
}

long long Document::integer(const std::string& path, std::size_t index) const {
  return std::get<long long>(entry(path, index, {Kind::Integer}, "integer").value);
}

bool Document::boolean(const std::string& path, std::size_t index) const {
  return std::get<bool>(entry(path, index, {Kind::Boolean}, "boolean").value);
}

const std::string& Document::string(const std::string& path, std::size_t index) const {
  return std::get<std::string>(entry(path, index, {Kind::String, Kind::Choice}, "string").value);
}

std::vector<double> Document::numbers(const std::string& path, std::size_t index) const {
  return std::get<std::vector<double>>(entry(path, index, {Kind::NumberList}, "numbers").value);
}

std::vector<std::string> Document::strings(const std::string& path, std::size_t index) const {
  return std::get<std::vector<std::string>>(entry(path, index, {Kind::StringList}, "strings").value);
}

bool Document::present(const std::string& path, std::size_t index) const {
  return entry(path, index, {}, "present").present;
}

std::string Document::where(const std::string& path, std::size_t index) const {
  return entry(path, index, {}, "where").where;
}

Issue Document::issue(const std::string& path, std::size_t index, std::string message) const {
  const Element& el = element(path, index, "issue");
  const Entry& e = el.entries.at(path);
  const auto dot = path.rfind('.');
  const std::string key = e.array + "[" + std::to_string(index) + "]" + path.substr(dot);
  if (!e.present) return Issue{el.file, el.line, el.column, key, std::move(message)};
  return Issue{e.file, e.line, e.column, key, std::move(message)};
}

std::string Document::value_text(const std::string& path, std::size_t index) const {
  return text::toml_value(entry(path, index, {}, "value_text").value);
}

std::vector<std::string> Document::element_key_paths(const std::string& array_path) const {
  count(array_path);  // refuses what is not an array
  return arrays_.at(array_path).keys;
}

}  // namespace ff::scene
