#include "core/scene/scene_edit.h"

#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "core/scene/scene.h"
#include "core/scene/schema.h"

namespace ff::scene {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

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

std::string scene_text_with_overrides(const std::string& path, const std::vector<std::string>& overrides) {
  const Schema& schema = scene_schema(path);
  const Document wanted = validate_file(schema, path, overrides);  // throws SceneError

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

  std::ifstream in(path, std::ios::binary);
  std::stringstream buf;
  buf << in.rdbuf();
  const std::string text = buf.str();
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

}  // namespace ff::scene
