#include "core/scene/schema.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/scene/schema_text.h"

namespace ff::scene {

// ---- ranges ---------------------------------------------------------------------------------

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  if (min && (min_inclusive ? x < *min : x <= *min)) return false;
  if (max && (max_inclusive ? x > *max : x >= *max)) return false;
  return true;
}

std::string Range::text() const {
  if (min && max)
    return std::string(min_inclusive ? "[" : "(") + text::number(*min) + ", " +
           text::number(*max) + (max_inclusive ? "]" : ")");
  if (min) return std::string(min_inclusive ? ">= " : "> ") + text::number(*min);
  if (max) return std::string(max_inclusive ? "<= " : "< ") + text::number(*max);
  return "any";
}

bool IntRange::contains(long long x) const {
  return (!min || x >= *min) && (!max || x <= *max);
}

std::string IntRange::text() const {
  if (min && max) {
    std::string s = "[";
    s += std::to_string(*min);
    s += ", ";
    s += std::to_string(*max);
    return s + "]";
  }
  if (min) return ">= " + std::to_string(*min);
  if (max) return "<= " + std::to_string(*max);
  return "any";
}

// ---- declarations ---------------------------------------------------------------------------

namespace {

std::string parent_of(std::string_view path) {
  const auto dot = path.rfind('.');
  return dot == std::string_view::npos ? std::string() : std::string(path.substr(0, dot));
}

std::string leaf_of(std::string_view path) {
  const auto dot = path.rfind('.');
  return std::string(dot == std::string_view::npos ? path : path.substr(dot + 1));
}

bool is_bare_key(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

[[noreturn]] void bad_declaration(const std::string& path, const std::string& why) {
  throw std::logic_error("scene schema: '" + path + "': " + why);
}

void check_range(const std::string& path, const Range& r) {
  if ((r.min && !std::isfinite(*r.min)) || (r.max && !std::isfinite(*r.max)))
    bad_declaration(path, "range bounds must be finite (leave a bound unset instead)");
  if (r.min && r.max && *r.min > *r.max) bad_declaration(path, "range min > max");
}

}  // namespace

void Schema::check_new_path(const std::string& path, const std::string& doc) const {
  if (path.empty()) bad_declaration(path, "empty path");
  std::size_t start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    const auto seg = std::string_view(path).substr(start, dot == std::string::npos
                                                              ? std::string::npos
                                                              : dot - start);
    if (!is_bare_key(seg))
      bad_declaration(path, "each path segment must be a TOML bare key [A-Za-z0-9_-]+");
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (find_table(path) || find_key(path)) bad_declaration(path, "declared twice");
  if (!find_table(parent_of(path)))
    bad_declaration(path, "its table '" + parent_of(path) + "' is not declared (declare it first)");
  if (doc.empty()) bad_declaration(path, "every table and key needs a one-line doc");
}

Schema& Schema::table(std::string path, std::string doc, bool required) {
  check_new_path(path, doc);
  if (find_array(parent_of(path)))
    bad_declaration(path, "tables inside an array of tables [[" + parent_of(path) +
                              "]] are not supported (elements hold plain keys only)");
  tables_.push_back(TableSpec{std::move(path), std::move(doc), required});
  return *this;
}

Schema& Schema::table_array(std::string path, std::string doc, std::size_t min_count,
                            std::size_t max_count) {
  check_new_path(path, doc);
  if (find_array(parent_of(path)))
    bad_declaration(path, "arrays of tables inside an array of tables [[" + parent_of(path) +
                              "]] are not supported (elements hold plain keys only)");
  if (max_count == 0) bad_declaration(path, "max_count 0 allows no element at all");
  if (min_count > max_count) bad_declaration(path, "min_count > max_count");
  TableSpec t{std::move(path), std::move(doc), min_count > 0};
  t.array = true;
  t.min_count = min_count;
  t.max_count = max_count;
  tables_.push_back(std::move(t));
  return *this;
}

Schema& Schema::add_key(KeySpec spec) {
  check_new_path(spec.path, spec.doc);
  const std::string& p = spec.path;
  check_range(p, spec.range);
  if (spec.int_range.min && spec.int_range.max && *spec.int_range.min > *spec.int_range.max)
    bad_declaration(p, "range min > max");
  if (spec.min_len > spec.max_len) bad_declaration(p, "min_len > max_len");
  if (spec.kind == Kind::Choice && spec.choices.empty()) bad_declaration(p, "no choices");
  for (std::size_t i = 0; i < spec.choices.size(); ++i)
    if (std::find(spec.choices.begin(), spec.choices.begin() + i, spec.choices[i]) !=
        spec.choices.begin() + i)
      bad_declaration(p, "choice '" + spec.choices[i] + "' listed twice");

  // a default must itself be valid input
  const auto allowed = [&](const std::string& s) {
    return spec.choices.empty() ||
           std::find(spec.choices.begin(), spec.choices.end(), s) != spec.choices.end();
  };
  const Value& d = spec.default_value;
  if (const double* x = std::get_if<double>(&d); x && (!std::isfinite(*x) || !spec.range.contains(*x)))
    bad_declaration(p, "default " + text::number(*x) + " is outside " + spec.range.text());
  if (const long long* n = std::get_if<long long>(&d); n && !spec.int_range.contains(*n))
    bad_declaration(p, "default " + std::to_string(*n) + " is outside " + spec.int_range.text());
  if (const std::string* s = std::get_if<std::string>(&d); s && !allowed(*s))
    bad_declaration(p, "default '" + *s + "' is not one of the choices");
  if (const auto* xs = std::get_if<std::vector<double>>(&d)) {
    if (xs->size() < spec.min_len || xs->size() > spec.max_len)
      bad_declaration(p, "default has a length outside the allowed lengths");
    for (double x : *xs)
      if (!std::isfinite(x) || !spec.range.contains(x))
        bad_declaration(p, "default element " + text::number(x) + " is outside " + spec.range.text());
  }
  if (const auto* ss = std::get_if<std::vector<std::string>>(&d)) {
    if (ss->size() < spec.min_len || ss->size() > spec.max_len)
      bad_declaration(p, "default has a length outside the allowed lengths");
    for (const auto& s : *ss)
      if (!allowed(s)) bad_declaration(p, "default element '" + s + "' is not allowed");
  }
  keys_.push_back(std::move(spec));
  return *this;
}

Schema& Schema::number(std::string path, std::string doc, std::optional<double> default_value,
                       Range range, std::string unit) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::Number;
  if (default_value) k.default_value = *default_value;
  k.range = range;
  k.unit = std::move(unit);
  return add_key(std::move(k));
}

Schema& Schema::integer(std::string path, std::string doc,
                        std::optional<long long> default_value, IntRange range) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::Integer;
  if (default_value) k.default_value = *default_value;
  k.int_range = range;
  return add_key(std::move(k));
}

Schema& Schema::boolean(std::string path, std::string doc, std::optional<bool> default_value) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::Boolean;
  if (default_value) k.default_value = *default_value;
  return add_key(std::move(k));
}

Schema& Schema::string(std::string path, std::string doc,
                       std::optional<std::string> default_value) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::String;
  if (default_value) k.default_value = std::move(*default_value);
  return add_key(std::move(k));
}

Schema& Schema::choice(std::string path, std::string doc, std::vector<std::string> choices,
                       std::optional<std::string> default_value) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::Choice;
  if (default_value) k.default_value = std::move(*default_value);
  k.choices = std::move(choices);
  return add_key(std::move(k));
}

Schema& Schema::number_list(std::string path, std::string doc,
                            std::optional<std::vector<double>> default_value, Range each,
                            std::size_t min_len, std::size_t max_len, std::string unit) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::NumberList;
  if (default_value) k.default_value = std::move(*default_value);
  k.range = each;
  k.min_len = min_len;
  k.max_len = max_len;
  k.unit = std::move(unit);
  return add_key(std::move(k));
}

Schema& Schema::string_list(std::string path, std::string doc,
                            std::optional<std::vector<std::string>> default_value,
                            std::vector<std::string> allowed) {
  KeySpec k;
  k.path = std::move(path);
  k.doc = std::move(doc);
  k.kind = Kind::StringList;
  if (default_value) k.default_value = std::move(*default_value);
  k.choices = std::move(allowed);
  return add_key(std::move(k));
}

Schema& Schema::live(std::string_view path) {
  const std::string p(path);
  auto it = std::find_if(keys_.begin(), keys_.end(), [&](const KeySpec& k) { return k.path == path; });
  if (it == keys_.end()) bad_declaration(p, "declared live but not declared as a key (declare it first)");
  // a live edit names one key of the running model; an element of [[array]] has no such name
  if (!array_of(path).empty()) bad_declaration(p, "keys of an array of tables cannot be live");
  it->live = true;
  return *this;
}

Schema& Schema::unit_of(std::string_view path, std::string unit) {
  const std::string p(path);
  const auto it = std::find_if(keys_.begin(), keys_.end(), [&](const KeySpec& k) { return k.path == p; });
  if (it == keys_.end()) bad_declaration(p, "given a unit but not declared as a key (declare it first)");
  if (it->kind != Kind::Number && it->kind != Kind::NumberList) bad_declaration(p, "a unit is for numbers");
  it->unit = std::move(unit);
  return *this;
}

bool Schema::KeySpec::applies(const std::string& condition_value) const {
  return condition_key.empty() ||
         std::find(condition_values.begin(), condition_values.end(), condition_value) != condition_values.end();
}

Schema& Schema::applies_when(std::string_view path, std::string condition_key, std::vector<std::string> values) {
  const std::string p(path);
  auto find = [&](const std::string& k) {
    return std::find_if(keys_.begin(), keys_.end(), [&](const KeySpec& spec) { return spec.path == k; });
  };
  const auto it = find(p);
  if (it == keys_.end()) bad_declaration(p, "given a condition but not declared as a key (declare it first)");
  const auto cond = find(condition_key);
  if (cond == keys_.end() || cond->kind != Kind::Choice)
    bad_declaration(p, "its condition key '" + condition_key + "' is not a declared choice key");
  if (parent_of(cond->path) != parent_of(p)) bad_declaration(p, "its condition key '" + condition_key + "' is in another table");
  for (const std::string& v : values)
    if (std::find(cond->choices.begin(), cond->choices.end(), v) == cond->choices.end())
      bad_declaration(p, "its condition value '" + v + "' is not a choice of '" + condition_key + "'");
  it->condition_key = std::move(condition_key);
  it->condition_values = std::move(values);
  return *this;
}

std::vector<std::string> Schema::live_keys() const {
  std::vector<std::string> out;
  for (const auto& k : keys_)
    if (k.live) out.push_back(k.path);
  return out;
}

// ---- lookup ---------------------------------------------------------------------------------

Schema& Schema::renamed(std::string old_path, std::string new_path) {
  renamed_[std::move(old_path)] = std::move(new_path);
  return *this;
}

std::string Schema::renamed_to(std::string_view indexed_path) const {
  // an element of an array of tables ("joint[0].body") is renamed as its array's key ("joint.body")
  std::string plain;
  for (std::size_t i = 0; i < indexed_path.size(); ++i) {
    if (indexed_path[i] == '[') {
      const std::size_t close = indexed_path.find(']', i);
      if (close != std::string_view::npos) {
        i = close;
        continue;
      }
    }
    plain += indexed_path[i];
  }
  const std::string_view path = plain;
  for (std::string_view p = path;; ) {
    if (auto it = renamed_.find(std::string(p)); it != renamed_.end())
      return it->second + std::string(path.substr(p.size()));
    const auto dot = p.rfind('.');
    if (dot == std::string_view::npos) return "";
    p = p.substr(0, dot);
  }
}

const Schema::TableSpec* Schema::find_table(std::string_view path) const {
  for (const auto& t : tables_)
    if (t.path == path) return &t;
  return nullptr;
}

const Schema::KeySpec* Schema::find_key(std::string_view path) const {
  for (const auto& k : keys_)
    if (k.path == path) return &k;
  return nullptr;
}

const Schema::TableSpec* Schema::find_array(std::string_view path) const {
  const TableSpec* t = find_table(path);
  return t && t->array ? t : nullptr;
}

std::string Schema::array_of(std::string_view key_path) const {
  const std::string parent = parent_of(key_path);
  return find_array(parent) ? parent : std::string();
}

std::vector<std::string> Schema::children(std::string_view table_path) const {
  std::vector<std::string> out;
  for (const auto& t : tables_)
    if (!t.path.empty() && parent_of(t.path) == table_path) out.push_back(leaf_of(t.path));
  for (const auto& k : keys_)
    if (parent_of(k.path) == table_path) out.push_back(leaf_of(k.path));
  return out;
}

// ---- markdown reference ---------------------------------------------------------------------

namespace {

std::string cell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

std::string code_list(const std::vector<std::string>& items) {
  std::vector<std::string> parts;
  for (const auto& s : items) parts.push_back("`" + s + "`");
  return text::join(parts, ", ");
}

std::string length_text(std::size_t lo, std::size_t hi) {
  if (lo == hi) return "length " + std::to_string(lo);
  if (hi == SIZE_MAX) return lo == 0 ? "" : "length >= " + std::to_string(lo);
  return "length " + std::to_string(lo) + " to " + std::to_string(hi);
}

std::string type_text(const Schema::KeySpec& k) {
  std::string unit = k.unit.empty() ? "" : " [" + k.unit + "]";
  switch (k.kind) {
    case Kind::Number: return "number" + unit;
    case Kind::Integer: return "integer";
    case Kind::Boolean: return "boolean";
    case Kind::String: return "string";
    case Kind::Choice: return "choice";
    case Kind::NumberList: return "list of numbers" + unit;
    case Kind::StringList: return "list of strings";
  }
  return "";
}

std::string allowed_text(const Schema::KeySpec& k) {
  switch (k.kind) {
    case Kind::Number: return k.range.text();
    case Kind::Integer: return k.int_range.text();
    case Kind::Boolean: return "`true`, `false`";
    case Kind::String: return "any";
    case Kind::Choice: return code_list(k.choices);
    case Kind::NumberList:
    case Kind::StringList: {
      std::vector<std::string> parts;
      if (auto len = length_text(k.min_len, k.max_len); !len.empty()) parts.push_back(len);
      if (k.kind == Kind::NumberList && !k.range.unbounded())
        parts.push_back("each " + k.range.text());
      if (k.kind == Kind::StringList && !k.choices.empty())
        parts.push_back("each one of " + code_list(k.choices));
      return parts.empty() ? "any" : text::join(parts, "; ");
    }
  }
  return "";
}

/// " (only with generator = cylinder, annulus)" for a key with a condition.
std::string condition_text(const Schema::KeySpec& k) {
  if (k.condition_key.empty()) return "";
  std::string values;
  for (const std::string& v : k.condition_values) values += (values.empty() ? "" : ", ") + v;
  return cell(" (only with " + k.condition_key.substr(k.condition_key.rfind('.') + 1) + " = " + values + ")");
}

/// "0 or more", "exactly 2", "1 to 3".
std::string count_text(const Schema::TableSpec& t) {
  if (t.min_count == t.max_count) return "exactly " + std::to_string(t.min_count);
  if (t.max_count == SIZE_MAX) return std::to_string(t.min_count) + " or more";
  return std::to_string(t.min_count) + " to " + std::to_string(t.max_count);
}

}  // namespace

std::string Schema::markdown_reference() const {
  std::string out;
  for (const auto& t : tables_) {
    std::vector<const KeySpec*> keys;
    for (const auto& k : keys_)
      if (parent_of(k.path) == t.path) keys.push_back(&k);
    if (t.path.empty() && keys.empty()) continue;

    if (t.array) {
      out += "### [[" + t.path + "]] (array of tables, " + count_text(t) + ")\n\n";
      out += cell(t.doc) + " (write one `[[" + t.path + "]]` table per element)\n\n";
    } else {
      out += t.path.empty() ? "### Top level\n\n" : "### `[" + t.path + "]`\n\n";
      if (!t.path.empty())
        out += cell(t.doc) + (t.required ? " (required table)" : " (optional table)") + "\n\n";
    }
    if (keys.empty()) {
      out += "No keys of its own.\n\n";
      continue;
    }
    out += "| key | type | default | allowed | meaning |\n";
    out += "|---|---|---|---|---|\n";
    for (const KeySpec* k : keys) {
      std::string def = "**required**";
      if (!k->required()) {
        def = "`";
        def += text::toml_value(k->default_value);
        def += "`";
      }
      out += "| `" + k->path + "` | " + cell(type_text(*k)) + " | " + cell(def) + " | " +
             cell(allowed_text(*k)) + " | " + cell(k->doc) +
             (k->live ? " (live: changes while the run goes on)" : "") + condition_text(*k) + " |\n";
    }
    out += "\n";
  }
  return out;
}

}  // namespace ff::scene
