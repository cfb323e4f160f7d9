#include "core/scene/scene_edit.h"

#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/frame/text.h"
#include "core/scene/scene.h"
#include "core/scene/schema.h"
#include "core/scene/schema_text.h"

namespace ff::scene {
namespace {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, sep);) out.push_back(item);
  return out;
}

/// One override, located: `table` segments (inside the array element when `array` is set),
/// `leaf` the key name, `value` its canonical TOML text.
struct Edit {
  std::string array;  ///< "" outside arrays of tables
  std::size_t index = 0;
  std::vector<std::string> table;
  std::string leaf;
  std::string value;
};

/// Byte offset of (line, column), both 1-based, columns counted in code points as toml++ does.
std::size_t offset_of(const std::string& text, std::size_t line, std::size_t column) {
  std::size_t pos = 0;
  for (std::size_t l = 1; l < line && pos < text.size(); ++l) {
    const auto nl = text.find('\n', pos);
    if (nl == std::string::npos) return text.size();
    pos = nl + 1;
  }
  for (std::size_t c = 1; c < column && pos < text.size() && text[pos] != '\n'; ++c) {
    ++pos;
    while (pos < text.size() && (static_cast<unsigned char>(text[pos]) & 0xC0) == 0x80) ++pos;
  }
  return pos;
}

/// Offset of the start of the line after `line`.
std::size_t after_line(const std::string& text, std::size_t line) {
  const std::size_t start = offset_of(text, line, 1);
  const auto nl = text.find('\n', start);
  return nl == std::string::npos ? text.size() : nl + 1;
}

std::string line_text(const std::string& text, std::size_t line) {
  const std::size_t a = offset_of(text, line, 1);
  const auto nl = text.find('\n', a);
  return text.substr(a, nl == std::string::npos ? std::string::npos : nl - a);
}

struct Splice {
  std::size_t begin, end;
  std::string text;
};

/// Places every edit into `text`; false when one has no obvious place (the caller falls back).
bool patch(const std::string& text, const std::string& path, const std::vector<Edit>& edits, std::string* out) {
  toml::table root;
  try {
    root = toml::parse(text, std::string_view(path));
  } catch (const toml::parse_error&) {
    return false;
  }
  std::vector<Splice> splices;
  std::string appended;
  for (const Edit& e : edits) {
    toml::node* base = &root;
    if (!e.array.empty()) {
      toml::array* arr = root[e.array].as_array();
      if (!arr || e.index >= arr->size() || !(*arr)[e.index].is_table()) return false;
      base = &(*arr)[e.index];
    }
    toml::node* table = base;
    bool table_found = true;
    for (const std::string& seg : e.table) {
      toml::table* t = table->as_table();
      toml::node* next = t ? t->get(seg) : nullptr;
      if (!next || !next->is_table()) {
        table_found = false;
        break;
      }
      table = next;
    }
    if (table_found) {
      toml::table* t = table->as_table();
      if (t->is_inline()) return false;
      if (toml::node* v = t->get(e.leaf)) {
        const auto& r = v->source();
        if (r.begin.line == 0 || r.end.line == 0) return false;
        splices.push_back({offset_of(text, r.begin.line, r.begin.column), offset_of(text, r.end.line, r.end.column),
                           e.value});
        continue;
      }
      const std::string line_to_add = e.leaf + " = " + e.value + "\n";
      if (table == &root) {
        // a top-level key goes before the first table header
        std::size_t line = 1, pos = 0;
        for (; pos < text.size(); ++line) {
          if (trim(line_text(text, line)).rfind('[', 0) == 0) break;
          const auto nl = text.find('\n', pos);
          pos = nl == std::string::npos ? text.size() : nl + 1;
        }
        splices.push_back({pos, pos, line_to_add});
        continue;
      }
      // a table with a header line ([name] or [[name]]): the key goes right below it
      const auto& r = table->source();
      if (r.begin.line == 0 || trim(line_text(text, r.begin.line)).rfind('[', 0) != 0) return false;
      const std::size_t at = after_line(text, r.begin.line);
      splices.push_back({at, at, line_to_add});
      continue;
    }
    // the table is missing: a new one at the end (only outside arrays of tables)
    if (!e.array.empty()) return false;
    std::string name;
    for (const std::string& seg : e.table) name += (name.empty() ? "" : ".") + seg;
    appended += "\n[" + name + "]\n" + e.leaf + " = " + e.value + "\n";
  }
  // splices never overlap (one per key); apply from the back so offsets stay valid
  std::stable_sort(splices.begin(), splices.end(), [](const Splice& a, const Splice& b) { return a.begin > b.begin; });
  std::string result = text;
  for (const Splice& s : splices) result.replace(s.begin, s.end - s.begin, s.text);
  if (!appended.empty()) {
    if (!result.empty() && result.back() != '\n') result += '\n';
    result += appended;
  }
  *out = result;
  return true;
}

/// The whole document rewritten by toml++ with the edits applied (comments are lost).
std::string rewrite(const std::string& text, const std::string& path, const std::vector<Edit>& edits) {
  toml::table root = toml::parse(text, std::string_view(path));
  for (const Edit& e : edits) {
    toml::table* t = &root;
    if (!e.array.empty()) t = root[e.array][e.index].as_table();
    if (!t) throw std::runtime_error("cannot place " + e.array + "[" + std::to_string(e.index) + "] in " + path);
    for (const std::string& seg : e.table) {
      if (!t->get(seg) || !t->get(seg)->is_table()) t->insert_or_assign(seg, toml::table{});
      t = t->get(seg)->as_table();
    }
    toml::table holder = toml::parse("v = " + e.value, std::string_view("value"));
    t->insert_or_assign(e.leaf, *holder.get("v"));
  }
  std::ostringstream out;
  out << "# written by flexframe from " << path << " (comments were not kept)\n" << root << "\n";
  return out.str();
}

/// Every validated value as text, keyed by path ("bc[1].type" for elements).
std::map<std::string, std::string> values_of(const Document& d) {
  std::map<std::string, std::string> m;
  for (const std::string& k : d.key_paths()) m[k] = d.value_text(k);
  for (const std::string& a : d.array_paths())
    for (std::size_t i = 0; i < d.count(a); ++i)
      for (const std::string& k : d.element_key_paths(a))
        m[a + "[" + std::to_string(i) + "]" + k.substr(a.size())] = d.value_text(k, i);
  return m;
}

}  // namespace

std::string edited_scene_text(const std::string& text, const std::string& path,
                              const std::vector<std::string>& overrides) {
  const Schema& schema = schema_for_text(text);
  const Document wanted = validate(schema, text, path, overrides);  // throws SceneError

  // one edit per key, the last override winning
  std::vector<Edit> edits;
  std::map<std::string, std::size_t> seen;
  for (const std::string& o : overrides) {
    const auto eq = o.find('=');
    const std::string key = trim(o.substr(0, eq));
    Edit e;
    std::string rest = key;
    if (const auto lb = key.find('['); lb != std::string::npos) {
      const auto rb = key.find(']', lb);
      e.array = key.substr(0, lb);
      e.index = std::stoul(key.substr(lb + 1, rb - lb - 1));
      rest = key.substr(rb + 2);
      e.value = wanted.value_text(e.array + "." + rest, e.index);
    } else {
      e.value = wanted.value_text(key);
    }
    std::vector<std::string> segs = split(rest, '.');
    e.leaf = segs.back();
    segs.pop_back();
    e.table = segs;
    if (auto it = seen.find(key); it != seen.end()) {
      edits[it->second] = e;
    } else {
      seen[key] = edits.size();
      edits.push_back(e);
    }
  }

  const auto want = values_of(wanted);
  auto reads_back = [&](const std::string& candidate) {
    try {
      return values_of(validate(schema, candidate, path)) == want;
    } catch (const SceneError&) {
      return false;
    }
  };
  std::string patched;
  if (patch(text, path, edits, &patched) && reads_back(patched)) return patched;
  std::string rewritten = rewrite(text, path, edits);
  if (!reads_back(rewritten))
    throw std::runtime_error("could not write the edited scene " + path + " so that it reads back the same");
  return rewritten;
}

std::string scene_text_with_overrides(const std::string& path, const std::vector<std::string>& overrides) {
  return edited_scene_text(read_scene_text(path), path, overrides);
}

namespace {

toml::table parsed(const std::string& text, const std::string& path) {
  try {
    return toml::parse(text, std::string_view(path));
  } catch (const toml::parse_error& e) {
    const auto& at = e.source().begin;
    throw SceneError({Issue{path, static_cast<int>(at.line), static_cast<int>(at.column), "",
                            std::string(e.description())}});
  }
}

bool is_header(const std::string& line) { return trim(line).rfind('[', 0) == 0; }
bool is_comment_or_blank(const std::string& line) {
  const std::string t = trim(line);
  return t.empty() || t[0] == '#';
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const auto nl = text.find('\n', pos);
    lines.push_back(text.substr(pos, nl == std::string::npos ? std::string::npos : nl + 1 - pos));
    pos = nl == std::string::npos ? text.size() : nl + 1;
  }
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l;
  return s;
}

/// The candidate text when it parses to `expected`, else the whole document written by toml++
/// (comments lost, said in a first line).
std::string checked_or_rewritten(const std::string& candidate, const toml::table& expected, const std::string& path) {
  try {
    if (toml::parse(candidate, std::string_view(path)) == expected) return candidate;
  } catch (const toml::parse_error&) {
  }
  std::ostringstream out;
  out << "# written by flexframe from " << path << " (comments were not kept)\n" << expected << "\n";
  return out.str();
}

/// 0-based line of the header of element `index` of [[array]]; npos when absent.
std::size_t header_line(const toml::table& root, const std::string& array, std::size_t index) {
  const toml::array* arr = root[array].as_array();
  if (!arr || index >= arr->size() || !(*arr)[index].is_table()) return std::string::npos;
  const auto line = (*arr)[index].source().begin.line;
  return line == 0 ? std::string::npos : line - 1;
}

}  // namespace

std::string toml_value_as_set_reads_it(const std::string& value) {
  try {
    (void)toml::parse("v = " + value);
    return value;
  } catch (const toml::parse_error&) {
    return text::quoted(value);
  }
}

std::string text_with_element(const std::string& text, const std::string& path, const std::string& array,
                              const std::vector<std::pair<std::string, std::string>>& keys,
                              std::optional<std::size_t> before) {
  const toml::table original = parsed(text, path);
  toml::table expected = original;
  toml::table element;
  std::string block = "[[" + array + "]]\n";
  for (const auto& [key, value] : keys) {
    const toml::table holder = parsed("v = " + value, path + " (" + array + "." + key + ")");
    element.insert_or_assign(key, *holder.get("v"));
    block += key + " = " + value + "\n";
  }
  toml::array* arr = expected[array].as_array();
  if (!arr) {
    expected.insert_or_assign(array, toml::array{});
    arr = expected[array].as_array();
  }
  const std::size_t at = before && *before < arr->size() ? *before : arr->size();
  arr->insert(arr->begin() + static_cast<std::ptrdiff_t>(at), element);

  std::vector<std::string> lines = lines_of(text);
  const std::size_t header = at < arr->size() - 1 ? header_line(original, array, at) : std::string::npos;
  if (header != std::string::npos) {
    lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(header), block + "\n");
  } else {
    if (!lines.empty() && lines.back().back() != '\n') lines.back() += '\n';
    lines.push_back("\n" + block);
  }
  return checked_or_rewritten(joined(lines), expected, path);
}

std::string text_without_element(const std::string& text, const std::string& path, const std::string& array,
                                 std::size_t index) {
  toml::table expected = parsed(text, path);
  toml::array* arr = expected[array].as_array();
  if (!arr || index >= arr->size())
    throw std::invalid_argument(path + ": there is no " + array + "[" + std::to_string(index) + "] to remove");
  const std::size_t first = header_line(expected, array, index);
  arr->erase(arr->begin() + static_cast<std::ptrdiff_t>(index));
  if (arr->empty()) expected.erase(array);

  std::vector<std::string> lines = lines_of(text);
  if (first == std::string::npos || first >= lines.size()) return checked_or_rewritten("", expected, path);
  // the element runs to the next header; comment lines right above that header belong to it
  std::size_t end = first + 1;
  while (end < lines.size() && !is_header(lines[end])) ++end;
  std::size_t keep_from = end;
  while (keep_from > first + 1 && is_comment_or_blank(lines[keep_from - 1])) --keep_from;
  if (end == lines.size()) keep_from = end;  // trailing comments of the last element go with it
  lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(first), lines.begin() + static_cast<std::ptrdiff_t>(keep_from));
  return checked_or_rewritten(joined(lines), expected, path);
}

std::string text_without_keys(const std::string& text, const std::string& path, const std::vector<std::string>& keys) {
  toml::table expected = parsed(text, path);
  std::vector<std::pair<std::size_t, std::size_t>> drop;  // 0-based line ranges [first, last]
  for (const std::string& key : keys) {
    toml::table* t = &expected;
    std::string rest = key;
    if (const auto lb = key.find('['); lb != std::string::npos) {
      const auto rb = key.find(']', lb);
      toml::array* arr = expected[key.substr(0, lb)].as_array();
      const std::size_t i = std::stoul(key.substr(lb + 1, rb - lb - 1));
      t = arr && i < arr->size() ? (*arr)[i].as_table() : nullptr;
      rest = key.substr(rb + 2);
    }
    std::vector<std::string> segs = split(rest, '.');
    const std::string leaf = segs.back();
    segs.pop_back();
    for (const std::string& seg : segs) t = t && t->get(seg) ? t->get(seg)->as_table() : nullptr;
    const toml::node* v = t ? t->get(leaf) : nullptr;
    if (!v) continue;  // nothing to drop
    const auto& r = v->source();
    if (r.begin.line > 0 && r.end.line >= r.begin.line) drop.emplace_back(r.begin.line - 1, r.end.line - 1);
    t->erase(leaf);
  }
  std::vector<std::string> lines = lines_of(text);
  std::sort(drop.begin(), drop.end(), std::greater<>());
  for (const auto& [first, last] : drop)
    if (last < lines.size()) lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(first), lines.begin() + static_cast<std::ptrdiff_t>(last + 1));
  return checked_or_rewritten(joined(lines), expected, path);
}

}  // namespace ff::scene
