// validate(): TOML text + overrides -> Document, or one SceneError listing every issue.
//
// Order of work: parse the file, walk it against the schema (unknown keys, wrong types, ranges),
// apply the --set overrides (each validated like a file value, replacing it), then fill defaults
// and report missing required tables and keys and element counts of arrays of tables. Issues are
// sorted by file position at the end.
//
// Keys of an array of tables [[bc]] are stored per element; issues name them 'bc[2].type' (the
// "shown" key), while the schema knows them as 'bc.type'.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "core/frame/text.h"
#include "core/scene/schema.h"
#include "core/frame/input_file.h"
#include "core/scene/schema_text.h"

namespace ff::scene {

namespace {

std::string parent_of(std::string_view path) {
  const auto dot = path.rfind('.');
  return dot == std::string_view::npos ? std::string() : std::string(path.substr(0, dot));
}

std::string join_path(const std::string& table, std::string_view leaf) {
  return table.empty() ? std::string(leaf) : table + "." + std::string(leaf);
}

bool is_bare_key(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

/// "a string ("abc")", "an integer (3)", "a list ([1, 2])", ... : what the input holds.
std::string describe(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string (" + text::quoted(text::clip(n.as_string()->get(), 40)) + ")";
    case toml::node_type::integer:
      return "an integer (" + std::to_string(n.as_integer()->get()) + ")";
    case toml::node_type::floating_point:
      return "a floating-point number (" + text::toml_number(n.as_floating_point()->get()) + ")";
    case toml::node_type::boolean:
      return std::string("a boolean (") + (n.as_boolean()->get() ? "true" : "false") + ")";
    case toml::node_type::array: {
      std::ostringstream os;
      os << *n.as_array();
      return "a list (" + text::clip(os.str(), 40) + ")";
    }
    case toml::node_type::table: return "a table";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    case toml::node_type::none: break;
  }
  return "nothing";
}

/// The value itself, for out-of-range messages: "-0.5", "0", "'fe'".
std::string bare(const toml::node& n) {
  if (auto* i = n.as_integer()) return std::to_string(i->get());
  if (auto* f = n.as_floating_point()) return text::number(f->get());
  if (auto* s = n.as_string()) return "'" + text::clip(s->get(), 40) + "'";
  return describe(n);
}

std::string with_range(const std::string& noun, const std::string& range_text, bool both_bounds) {
  if (range_text == "any") return noun;
  return noun + (both_bounds ? " in " : " ") + range_text;
}

std::string number_phrase(const Range& r) {
  return with_range("a number", r.text(), r.min && r.max);
}

std::string integer_phrase(const IntRange& r) {
  return with_range("an integer", r.text(), r.min && r.max);
}

std::string one_of(const std::vector<std::string>& choices) {
  return "one of " + text::join(choices, ", ");
}

std::string list_phrase(const Schema::KeySpec& k) {
  std::string s = k.kind == Kind::NumberList ? "a list of numbers" : "a list of strings";
  if (k.min_len == k.max_len)
    s += " (length " + std::to_string(k.min_len) + ")";
  else if (k.max_len != SIZE_MAX)
    s += " (length " + std::to_string(k.min_len) + " to " + std::to_string(k.max_len) + ")";
  else if (k.min_len > 0)
    s += " (length >= " + std::to_string(k.min_len) + ")";
  if (k.kind == Kind::NumberList && !k.range.unbounded()) s += ", each " + k.range.text();
  if (k.kind == Kind::StringList && !k.choices.empty()) s += ", each " + one_of(k.choices);
  return s;
}

/// "[[bc]] table" / "[[bc]] tables" after a count.
std::string tables_noun(const std::string& array, std::size_t n) {
  return "[[" + array + "]] table" + (n == 1 ? "" : "s");
}

/// "bc[2]"
std::string element_name(const std::string& array, std::size_t index) {
  return array + "[" + std::to_string(index) + "]";
}

std::optional<double> as_number(const toml::node& n) {
  if (auto* i = n.as_integer()) return static_cast<double>(i->get());
  if (auto* f = n.as_floating_point()) return f->get();
  return std::nullopt;
}

}  // namespace

/// Builds one Document; friend of Document. Internal to this file.
class DocumentBuilder {
 public:
  DocumentBuilder(const Schema& schema, std::string_view text, const std::string& file_name,
                  const std::vector<std::string>& overrides)
      : schema_(schema), text_(text), file_(file_name), overrides_(overrides) {
    doc_.text_ = std::string(text);
    doc_.file_name_ = file_name;
    for (const auto& t : schema.tables()) {
      if (t.array) {
        doc_.arrays_[t.path];
        doc_.array_order_.push_back(t.path);
      } else {
        doc_.tables_[t.path] = t.path.empty();
      }
    }
    for (const auto& k : schema.keys()) {
      auto& e = doc_.entries_[k.path];
      e.kind = k.kind;
      e.array = schema.array_of(k.path);
      if (e.array.empty())
        doc_.order_.push_back(k.path);
      else
        doc_.arrays_[e.array].keys.push_back(k.path);
    }
  }

  /// One live edit `key=value`, checked as an override of a live key would be; throws SceneError.
  Value live_value(const std::string& key, const std::string& value) {
    const Origin o{"live " + key + "=" + value, false};
    const Schema::KeySpec* spec = schema_.find_key(key);
    Value v;
    if (!spec || !spec->live) {
      const std::vector<std::string> live = schema_.live_keys();
      add({o.file, 0, 0, key,
           "'" + key + "' cannot change while the model runs (" +
               (live.empty() ? std::string("this model has no live keys")
                             : "live keys: " + text::join(live, ", ")) +
               ")"},
          2);
    } else if (toml::table holder; override_value(*spec, key, value, o, holder)) {
      v = check(*spec, *holder.get("v"), o, key);
    }
    if (!ranked_.empty()) throw SceneError(sorted_issues());
    return v;
  }

  Document run() {
    bool parsed = false;
    try {
      toml::table root = toml::parse(text_, file_);
      parsed = parsed_ = true;
      walk(root, "");
    } catch (const toml::parse_error& e) {
      const auto& at = e.source().begin;
      add({file_, static_cast<int>(at.line), static_cast<int>(at.column), "",
           "TOML syntax error: " + std::string(e.description())});
    }
    for (const auto& arg : overrides_) apply_override(arg);
    // after a syntax error the file's content is unknown: "missing" would be noise
    if (parsed) fill_defaults_and_check_required();
    if (!ranked_.empty()) throw SceneError(sorted_issues());
    return std::move(doc_);
  }

 private:
  // where an issue or a value comes from: the file (positions from toml++) or one --set
  struct Origin {
    std::string file;
    bool in_file = true;
  };

  struct Ranked {
    Issue issue;
    int group;  // 0 file with line, 1 file without line, 2 override
    std::size_t seq;
  };

  void add(Issue issue, int group = -1) {
    if (group < 0) group = issue.line > 0 ? 0 : 1;
    ranked_.push_back({std::move(issue), group, ranked_.size()});
  }

  void add_at(const Origin& o, const toml::source_region& src, const std::string& key,
              std::string message) {
    if (o.in_file)
      add({o.file, static_cast<int>(src.begin.line), static_cast<int>(src.begin.column), key,
           std::move(message)});
    else
      add({o.file, 0, 0, key, std::move(message)}, 2);
  }

  std::vector<Issue> sorted_issues() {
    std::stable_sort(ranked_.begin(), ranked_.end(), [](const Ranked& a, const Ranked& b) {
      if (a.group != b.group) return a.group < b.group;
      if (a.group == 0 && a.issue.line != b.issue.line) return a.issue.line < b.issue.line;
      if (a.group == 0 && a.issue.column != b.issue.column) return a.issue.column < b.issue.column;
      return a.seq < b.seq;
    });
    std::vector<Issue> out;
    for (auto& r : ranked_) out.push_back(std::move(r.issue));
    return out;
  }

  static std::string position(const std::string& file, const toml::source_region& src) {
    return file + ":" + std::to_string(src.begin.line) + ":" + std::to_string(src.begin.column);
  }

  // ---- unknown keys ---------------------------------------------------------------------------

  /// "unknown key 'solver.dtt' (did you mean 'solver.dt'?)"; `table` is the declared table (or
  /// array of tables) the unknown `name` was found in, `rest` any further path segments
  /// (overrides only), `shown_table` how the table is named in the message ("bc[2]" for an
  /// element of [[bc]]; `table` when empty).
  std::string unknown_message(const std::string& table, const std::string& name,
                              const std::string& rest, const std::string& shown_table = "") const {
    const std::string& prefix = shown_table.empty() ? table : shown_table;
    const std::string shown = join_path(prefix, name) + (rest.empty() ? "" : "." + rest);
    std::string msg = "unknown key '" + shown + "'";

    std::string best = text::closest(name, schema_.children(table));
    if (!best.empty()) {
      const std::string real = join_path(table, best);
      std::string guess = join_path(prefix, best);
      if (!rest.empty() && (schema_.find_key(real + "." + rest) || schema_.find_table(real + "." + rest)))
        guess += "." + rest;
      return msg + " (did you mean '" + guess + "'?)";
    }
    // the right name in the wrong table: 'dt' at top level when it belongs in [solver]
    if (rest.empty()) {
      for (const auto& k : schema_.keys())
        if (k.path.size() > name.size() && k.path.ends_with("." + name)) {
          if (const std::string array = schema_.array_of(k.path); !array.empty())
            return msg + " (did you mean '" + name + "' in a [[" + array + "]] table?)";
          return msg + " (did you mean '" + k.path + "'?)";
        }
    }
    auto names = schema_.children(table);
    if (!names.empty() && names.size() <= 12) {
      if (table.empty())
        msg += "; top-level keys are: " + text::join(names, ", ");
      else if (schema_.find_array(table))
        msg += "; keys in [[" + table + "]] are: " + text::join(names, ", ");
      else
        msg += "; keys in [" + table + "] are: " + text::join(names, ", ");
    }
    return msg;
  }

  // ---- the file -------------------------------------------------------------------------------

  void walk(const toml::table& table, const std::string& path) {
    const Origin origin{file_, true};
    for (auto&& [k, node] : table) {
      const std::string name(k.str());
      if (!is_bare_key(name)) {
        // a quoted key such as "solver.dt" = 1 must not pose as the dotted path
        add_at(origin, k.source(), join_path(path, text::quoted(name)),
               "unknown key '" + join_path(path, text::quoted(name)) +
                   "' (scene keys are plain names: letters, digits, '_' and '-')");
        continue;
      }
      const std::string full = join_path(path, name);
      if (const auto* t = schema_.find_table(full)) {
        if (t->array) {
          walk_array(*t, node);
        } else if (const auto* sub = node.as_table()) {
          doc_.tables_[full] = true;
          table_source_[full] = sub->source();
          walk(*sub, full);
        } else if (node.is_array_of_tables() && !node.as_array()->empty()) {
          add_at(origin, node.source(), full,
                 "expected a table [" + full + "] (" + t->doc + "), got an array of tables [[" +
                     full + "]]; [" + full + "] is a single table: write its header once, as [" +
                     full + "]");
          invalid_.insert(full);
        } else {
          add_at(origin, node.source(), full,
                 "expected a table [" + full + "] (" + t->doc + "), got " + describe(node));
          invalid_.insert(full);
        }
      } else if (const auto* spec = schema_.find_key(full)) {
        Value v = check(*spec, node, origin, full);
        if (std::holds_alternative<std::monostate>(v)) {
          invalid_.insert(full);
        } else {
          auto& e = doc_.entries_[full];
          e.value = std::move(v);
          e.present = true;
          e.where = position(file_, node.source());
          e.file = file_;
          e.line = static_cast<int>(node.source().begin.line);
          e.column = static_cast<int>(node.source().begin.column);
        }
      } else if (const std::string now = schema_.renamed_to(full); !now.empty()) {
        add_at(origin, k.source(), full, "'" + full + "' was renamed to '" + now + "'");
      } else if (const auto* sub = node.as_table(); sub && renamed_inside(full)) {
        // a table whose keys moved (e.g. [time] into [solver]): each key says where it went
        for (auto&& [k2, n2] : *sub) {
          const std::string key = join_path(full, std::string(k2.str()));
          const std::string to = schema_.renamed_to(key);
          add_at(origin, k2.source(), key, to.empty() ? unknown_message(path, name, std::string(k2.str()))
                                                      : "'" + key + "' was renamed to '" + to + "'");
        }
      } else if (const auto* arr = node.as_array(); arr && arr->is_array_of_tables() && renamed_inside(full)) {
        // an array of tables whose keys moved (e.g. [[shell]] into [[part]] and [[material]])
        for (std::size_t i = 0; i < arr->size(); ++i)
          if (const auto* element = (*arr)[i].as_table())
            for (auto&& [k2, n2] : *element) {
              const std::string key = full + "[" + std::to_string(i) + "]." + std::string(k2.str());
              const std::string to = schema_.renamed_to(key);
              add_at(origin, k2.source(), key, to.empty() ? unknown_message(path, name, std::string(k2.str()))
                                                          : "'" + key + "' was renamed to '" + to + "'");
            }
      } else {
        add_at(origin, k.source(), full, unknown_message(path, name, ""));
      }
    }
  }

  // some renamed key lives below `table`
  bool renamed_inside(const std::string& table) const {
    for (const auto& [old, now] : schema_.renames())
      if (old.rfind(table + ".", 0) == 0) return true;
    return false;
  }

  /// The array of tables `a.path` (found in a present table): each element is walked like a
  /// table, its values stored per element.
  void walk_array(const Schema::TableSpec& a, const toml::node& node) {
    const Origin origin{file_, true};
    const std::string& path = a.path;
    const auto* arr = node.as_array();
    if (!arr) {
      if (node.is_table())
        add_at(origin, node.source(), path,
               "expected an array of tables [[" + path + "]] (" + a.doc +
                   "), got a single table [" + path + "]; write each element under its own [[" +
                   path + "]] header (or as " + path + " = [{ ... }, { ... }])");
      else
        add_at(origin, node.source(), path,
               "expected an array of tables [[" + path + "]] (" + a.doc + "), got " + describe(node));
      invalid_.insert(path);
      return;
    }
    auto& elements = doc_.arrays_[path].elements;
    elements.clear();
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::node& el = *arr->get(i);
      Document::Element element;
      element.file = file_;
      element.line = static_cast<int>(el.source().begin.line);
      element.column = static_cast<int>(el.source().begin.column);
      for (const auto& key : doc_.arrays_[path].keys) {
        auto& e = element.entries[key];
        e.kind = doc_.entries_[key].kind;
        e.array = path;
      }
      elements.push_back(std::move(element));
      if (const auto* t = el.as_table()) {
        walk_element(*t, path, i);
      } else {
        add_at(origin, el.source(), element_name(path, i),
               "expected each element of [[" + path + "]] to be a table { ... }, got " + describe(el));
        invalid_.insert(element_name(path, i));
      }
    }
  }

  /// Element `index` of the array of tables `array`: plain keys only.
  void walk_element(const toml::table& table, const std::string& array, std::size_t index) {
    const Origin origin{file_, true};
    const std::string prefix = element_name(array, index);
    for (auto&& [k, node] : table) {
      const std::string name(k.str());
      if (!is_bare_key(name)) {
        const std::string shown = prefix + "." + text::quoted(name);
        add_at(origin, k.source(), shown,
               "unknown key '" + shown + "' (scene keys are plain names: letters, digits, '_' and '-')");
        continue;
      }
      const std::string full = array + "." + name;
      const std::string shown = prefix + "." + name;
      if (const auto* spec = schema_.find_key(full)) {
        Value v = check(*spec, node, origin, shown);
        if (std::holds_alternative<std::monostate>(v)) {
          invalid_.insert(shown);
        } else {
          auto& e = doc_.arrays_[array].elements[index].entries[full];
          e.value = std::move(v);
          e.present = true;
          e.where = position(file_, node.source());
          e.file = file_;
          e.line = static_cast<int>(node.source().begin.line);
          e.column = static_cast<int>(node.source().begin.column);
        }
      } else if (node.is_table() || node.is_array_of_tables()) {
        auto names = schema_.children(array);
        add_at(origin, node.source(), shown,
               "nested table '" + shown + "' is not allowed: [[" + array +
                   "]] elements hold plain keys only" +
                   (names.empty() ? std::string() : " (" + text::join(names, ", ") + ")"));
      } else if (const std::string now = schema_.renamed_to(full); !now.empty()) {
        add_at(origin, k.source(), shown, "'" + shown + "' was renamed to '" + now + "'");
      } else {
        add_at(origin, k.source(), shown, unknown_message(array, name, "", prefix));
      }
    }
  }

  // ---- one value against its declaration; monostate after reporting an issue -----------------

  /// `shown` names the key in issues: k.path, or "bc[2].type" for a key of an element.
  Value check(const Schema::KeySpec& k, const toml::node& n, const Origin& o,
              const std::string& shown) {
    const auto fail = [&](const toml::node& at, std::string msg) -> Value {
      add_at(o, at.source(), shown, std::move(msg));
      return std::monostate{};
    };
    switch (k.kind) {
      case Kind::Number: {
        const std::string want = number_phrase(k.range);
        auto x = as_number(n);
        if (!x) return fail(n, "expected " + want + ", got " + describe(n));
        if (!std::isfinite(*x)) return fail(n, "expected a finite number, got " + bare(n));
        if (!k.range.contains(*x)) return fail(n, "expected " + want + ", got " + bare(n));
        return *x;
      }
      case Kind::Integer: {
        const std::string want = integer_phrase(k.int_range);
        if (auto* f = n.as_floating_point()) {
          const double x = f->get();
          std::string hint = std::isfinite(x) && x == std::floor(x)
                                 ? " (write it without a decimal point)" : "";
          return fail(n, "expected " + want + ", got " + describe(n) + hint);
        }
        auto* i = n.as_integer();
        if (!i) return fail(n, "expected " + want + ", got " + describe(n));
        if (!k.int_range.contains(i->get())) return fail(n, "expected " + want + ", got " + bare(n));
        return static_cast<long long>(i->get());
      }
      case Kind::Boolean: {
        auto* b = n.as_boolean();
        if (!b) return fail(n, "expected " + text::kind_noun(k.kind) + ", got " + describe(n));
        return b->get();
      }
      case Kind::String: {
        auto* s = n.as_string();
        if (!s) return fail(n, "expected a string, got " + describe(n));
        return s->get();
      }
      case Kind::Choice: {
        auto* s = n.as_string();
        if (!s) return fail(n, "expected " + one_of(k.choices) + ", got " + describe(n));
        if (auto msg = choice_problem(k.choices, s->get()); !msg.empty()) return fail(n, msg);
        return s->get();
      }
      case Kind::NumberList:
      case Kind::StringList: return check_list(k, n, o, fail);
    }
    return std::monostate{};
  }

  /// "" when `s` is allowed, else "expected one of a, b, got 'c'" with a suggestion if close.
  static std::string choice_problem(const std::vector<std::string>& choices, const std::string& s) {
    if (choices.empty() || std::find(choices.begin(), choices.end(), s) != choices.end()) return "";
    std::string msg = "expected " + one_of(choices) + ", got '" + text::clip(s, 40) + "'";
    if (auto best = text::closest(s, choices); !best.empty()) msg += " (did you mean '" + best + "'?)";
    return msg;
  }

  template <class Fail>
  Value check_list(const Schema::KeySpec& k, const toml::node& n, const Origin& o, Fail fail) {
    const std::string want = list_phrase(k);
    auto* arr = n.as_array();
    if (!arr) return fail(n, "expected " + want + ", got " + describe(n));
    if (arr->size() < k.min_len || arr->size() > k.max_len)
      return fail(n, "expected " + want + ", got " + std::to_string(arr->size()) +
                         (arr->size() == 1 ? " element" : " elements"));
    bool ok = true;
    std::vector<double> numbers;
    std::vector<std::string> strings;
    for (std::size_t i = 0; i < arr->size(); ++i) {
      const toml::node& el = *arr->get(i);
      const std::string prefix = "element [" + std::to_string(i) + "]: ";
      if (k.kind == Kind::NumberList) {
        const std::string el_want = number_phrase(k.range);
        auto x = as_number(el);
        std::string msg;
        if (!x) msg = "expected " + el_want + ", got " + describe(el);
        else if (!std::isfinite(*x)) msg = "expected a finite number, got " + bare(el);
        else if (!k.range.contains(*x)) msg = "expected " + el_want + ", got " + bare(el);
        if (!msg.empty()) {
          fail(el, prefix + msg);
          ok = false;
        } else {
          numbers.push_back(*x);
        }
      } else {
        auto* s = el.as_string();
        std::string msg = s ? choice_problem(k.choices, s->get())
                            : "expected a string, got " + describe(el);
        if (!msg.empty()) {
          fail(el, prefix + msg);
          ok = false;
        } else {
          strings.push_back(s->get());
        }
      }
    }
    if (!ok) return std::monostate{};
    if (k.kind == Kind::NumberList) return numbers;
    return strings;
  }

  // ---- overrides ------------------------------------------------------------------------------

  void apply_override(const std::string& arg) {
    const Origin o{"--set " + arg, false};
    const auto issue = [&](const std::string& key, std::string msg) {
      add({o.file, 0, 0, key, std::move(msg)}, 2);
    };
    const auto eq = arg.find('=');
    if (eq == std::string::npos) {
      const std::string key = trim(arg);
      if (schema_.find_key(key) && schema_.array_of(key).empty())
        issue(key, "missing '=value': write --set " + key + "=VALUE");
      else
        issue("", "expected the form key=value (for example --set solver.dt=0.01), got '" +
                      text::clip(arg, 60) + "' with no '='");
      return;
    }
    const std::string key = trim(std::string_view(arg).substr(0, eq));
    const std::string value = trim(std::string_view(arg).substr(eq + 1));
    if (key.empty()) {
      issue("", "expected the form key=value, but the key before '=' is empty");
      return;
    }
    if (key.find('[') != std::string::npos) {
      apply_element_override(o, key, value);
      return;
    }
    if (schema_.find_array(key)) {
      const auto names = schema_.children(key);
      issue(key, "'" + key + "' is an array of tables [[" + key +
                     "]]; --set cannot replace a whole array, only a key of an element the file has" +
                     (names.empty() ? std::string()
                                    : ", such as '" + key + "[0]." + names.front() + "'"));
      return;
    }
    if (schema_.find_table(key)) {
      const auto names = schema_.children(key);
      issue(key, "'" + key + "' is a table; --set needs a key inside it" +
                     (names.empty() ? std::string() : ", such as '" + key + "." + names.front() + "'"));
      return;
    }
    const auto* spec = schema_.find_key(key);
    if (!spec) {
      // a path through an array of tables needs an element index
      for (auto dot = key.find('.'); dot != std::string::npos; dot = key.find('.', dot + 1)) {
        const std::string array = key.substr(0, dot);
        if (schema_.find_array(array)) {
          issue(key, "'" + array + "' is an array of tables [[" + array +
                         "]]; name the element: --set " + array + "[INDEX]." + key.substr(dot + 1) +
                         "=VALUE (elements count from 0)");
          return;
        }
      }
      issue(key, unknown_path_message(key));
      return;
    }
    if (const std::string array = schema_.array_of(key); !array.empty()) {
      const std::string leaf = key.substr(array.size() + 1);
      issue(key, "'" + key + "' is a key of the array of tables [[" + array +
                     "]]; name the element: --set " + array + "[INDEX]." + leaf +
                     "=VALUE (elements count from 0)");
      return;
    }

    toml::table holder;
    if (!override_value(*spec, key, value, o, holder)) return;
    Value v = check(*spec, *holder.get("v"), o, key);
    if (std::holds_alternative<std::monostate>(v)) {
      invalid_.insert(key);
      return;
    }
    auto& e = doc_.entries_[key];
    e.value = std::move(v);
    e.present = true;
    e.where = o.file;
    e.file = o.file;
    e.line = e.column = 0;
    invalid_.erase(key);
    for (std::string t = parent_of(key); !t.empty(); t = parent_of(t)) doc_.tables_[t] = true;
  }

  /// "unknown key ..." for an undeclared dotted `path`: the deepest declared table on the path
  /// holds the unknown segment.
  std::string unknown_path_message(const std::string& path) const {
    if (const std::string now = schema_.renamed_to(path); !now.empty()) return "'" + path + "' was renamed to '" + now + "'";
    std::string table;
    std::string rest = path;
    while (true) {
      const auto dot = rest.find('.');
      if (dot == std::string::npos) break;
      const std::string next = join_path(table, rest.substr(0, dot));
      if (!schema_.find_table(next)) break;
      table = next;
      rest = rest.substr(dot + 1);
    }
    const auto dot = rest.find('.');
    const std::string name = rest.substr(0, dot);
    const std::string tail = dot == std::string::npos ? "" : rest.substr(dot + 1);
    return unknown_message(table, name, tail);
  }

  /// The override's value as TOML in `holder["v"]`; false after reporting an issue.
  bool override_value(const Schema::KeySpec& spec, const std::string& key, const std::string& value,
                      const Origin& o, toml::table& holder) {
    const auto issue = [&](std::string msg) { add({o.file, 0, 0, key, std::move(msg)}, 2); };
    // an empty value is only meaningful for a plain string
    if (value.empty() && spec.kind != Kind::String) {
      issue("no value after '=': write --set " + key + "=VALUE, VALUE being " +
            text::kind_noun(spec.kind));
      return false;
    }
    // the value is TOML (0.01, true, "s", [1, 2]); a bare word that is not TOML is a string
    std::optional<toml::table> parsed;
    try {
      toml::table t = toml::parse("v = " + value, o.file);
      if (t.size() == 1 && t.contains("v")) parsed = std::move(t);
    } catch (const toml::parse_error& e) {
      if (!value.empty() && std::string_view("[{\"'").find(value.front()) != std::string_view::npos) {
        issue("value " + text::clip(value, 40) + " is not valid TOML: " + std::string(e.description()));
        return false;
      }
    }
    // for a plain string or a choice the raw text is meant (--set model.name=2024), unless quoted
    const bool wants_string = spec.kind == Kind::String || spec.kind == Kind::Choice;
    if (parsed && wants_string && !parsed->get("v")->is_string()) parsed.reset();
    if (parsed) {
      holder = std::move(*parsed);
    } else {
      holder = toml::table{};
      holder.insert("v", value);
    }
    return true;
  }

  /// `--set bc[1].type=fix`: a key of an element the file already has.
  void apply_element_override(const Origin& o, const std::string& key, const std::string& value) {
    const auto issue = [&](std::string msg) { add({o.file, 0, 0, key, std::move(msg)}, 2); };
    const auto lb = key.find('[');
    const std::string array = key.substr(0, lb);
    if (!schema_.find_array(array)) {
      if (schema_.find_table(array))
        issue("'" + array + "' is a table, not an array of tables: write --set " + array +
              ".KEY=VALUE, without an index");
      else if (schema_.find_key(array))
        issue("'" + array + "' is a key, not an array of tables: write --set " + array +
              "=VALUE, without an index");
      else
        issue(array.empty() ? "expected --set ARRAY[INDEX].KEY=VALUE, got '" + text::clip(key, 60) + "'"
                            : unknown_path_message(array));
      return;
    }
    const auto rb = key.find(']', lb);
    const std::string digits = rb == std::string::npos ? "" : key.substr(lb + 1, rb - lb - 1);
    const bool digits_ok = !digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) {
      return std::isdigit(static_cast<unsigned char>(c));
    });
    const std::string after = rb == std::string::npos ? "" : key.substr(rb + 1);
    const std::string form = "--set " + array + "[INDEX].KEY=VALUE, INDEX counting the [[" + array +
                             "]] tables from 0";
    if (!digits_ok) {
      issue("expected " + form + ", got '" + text::clip(key, 60) + "'");
      return;
    }
    if (after.empty()) {
      issue("--set cannot replace a whole element " + key + "; set its keys one by one: --set " + key +
            ".KEY=VALUE");
      return;
    }
    if (after.front() != '.' || after.size() == 1) {
      issue("expected " + form + ", got '" + text::clip(key, 60) + "'");
      return;
    }
    std::size_t index = SIZE_MAX;
    std::from_chars(digits.data(), digits.data() + digits.size(), index);  // overflow: past the end
    const std::string prefix = element_name(array, index);

    const std::string rest = after.substr(1);
    const auto dot = rest.find('.');
    const std::string name = rest.substr(0, dot);
    const std::string tail = dot == std::string::npos ? "" : rest.substr(dot + 1);
    const std::string full = array + "." + name;
    const auto* spec = tail.empty() ? schema_.find_key(full) : nullptr;
    if (!spec) {
      if (!tail.empty() && schema_.find_key(full))
        issue("'" + prefix + "." + name + "' is " + text::kind_noun(schema_.find_key(full)->kind) +
              ", it has no key '" + tail + "'");
      else
        issue(unknown_message(array, name, tail, prefix));
      return;
    }

    // the element must exist in the file (unknown after a syntax error or a refused array)
    const bool known = parsed_ && !invalid_.count(array);
    auto& elements = doc_.arrays_[array].elements;
    if (known && index >= elements.size()) {
      const std::string index_text = index == SIZE_MAX ? digits : std::to_string(index);
      std::string has;
      if (elements.empty())
        has = file_ + " has no [[" + array + "]] table";
      else if (elements.size() == 1)
        has = file_ + " has 1 [[" + array + "]] table, " + array + "[0]";
      else
        has = file_ + " has " + std::to_string(elements.size()) + " [[" + array + "]] tables, " +
              array + "[0] to " + element_name(array, elements.size() - 1);
      issue("index " + index_text + " is past the end: " + has +
            "; --set can only change a key of an element the file has");
      return;
    }

    const std::string shown = prefix + "." + name;
    toml::table holder;
    if (!override_value(*spec, shown, value, o, holder)) return;
    Value v = check(*spec, *holder.get("v"), o, shown);
    if (std::holds_alternative<std::monostate>(v)) {
      invalid_.insert(shown);
      return;
    }
    if (!known || invalid_.count(prefix)) return;  // nothing to store into; already reported
    auto& e = elements[index].entries[full];
    e.value = std::move(v);
    e.present = true;
    e.where = o.file;
    e.file = o.file;
    e.line = e.column = 0;
    invalid_.erase(shown);
  }

  // ---- defaults and required ------------------------------------------------------------------

  void fill_defaults_and_check_required() {
    for (const auto& t : schema_.tables()) {
      if (t.array) {
        check_count(t);
        continue;
      }
      if (t.path.empty() || !t.required || doc_.tables_[t.path] || invalid_.count(t.path)) continue;
      if (!doc_.tables_[parent_of(t.path)]) continue;  // optional parent absent
      add({file_, 0, 0, t.path,
           "missing required table [" + t.path + "] (meaning: " + t.doc + ")"});
    }
    for (const auto& k : schema_.keys()) {
      if (const std::string array = schema_.array_of(k.path); !array.empty()) {
        fill_element_keys(k, array);
        continue;
      }
      auto& e = doc_.entries_[k.path];
      if (e.present || invalid_.count(k.path)) continue;
      if (!k.required()) {
        e.value = k.default_value;
        e.where = "default";
        continue;
      }
      const std::string table = parent_of(k.path);
      if (!doc_.tables_[table] || invalid_.count(table)) continue;  // absent: table_present() says so
      int line = 0, column = 0;
      if (auto it = table_source_.find(table); it != table_source_.end()) {
        line = static_cast<int>(it->second.begin.line);
        column = static_cast<int>(it->second.begin.column);
      }
      add({file_, line, column, k.path,
           "missing required key '" + k.path + "' (meaning: " + k.doc + ")"});
    }
  }

  /// min_count <= elements <= max_count, when the array's parent table is present.
  void check_count(const Schema::TableSpec& a) {
    const std::string parent = parent_of(a.path);
    if (!doc_.tables_[parent] || invalid_.count(parent) || invalid_.count(a.path)) return;
    const auto& elements = doc_.arrays_[a.path].elements;
    const std::size_t n = elements.size();
    const auto report = [&](const char* bound, std::size_t limit, const Document::Element* at) {
      std::string msg = "expected ";
      msg += a.min_count == a.max_count ? "exactly" : bound;
      msg += " " + std::to_string(limit) + " " + tables_noun(a.path, limit) + ", got " +
             std::to_string(n);
      if (at)
        add({at->file, at->line, at->column, a.path, std::move(msg)});
      else
        add({file_, 0, 0, a.path, std::move(msg)});
    };
    if (n < a.min_count) report("at least", a.min_count, n ? &elements.front() : nullptr);
    if (n > a.max_count) report("at most", a.max_count, &elements[a.max_count]);
  }

  /// Key `k` of every element of `array`: default, or missing when required.
  void fill_element_keys(const Schema::KeySpec& k, const std::string& array) {
    auto& elements = doc_.arrays_[array].elements;
    for (std::size_t i = 0; i < elements.size(); ++i) {
      const std::string prefix = element_name(array, i);
      const std::string shown = prefix + k.path.substr(array.size());
      auto& el = elements[i];
      auto& e = el.entries[k.path];
      if (e.present || invalid_.count(shown) || invalid_.count(prefix)) continue;
      if (!k.required()) {
        e.value = k.default_value;
        e.where = "default";
        continue;
      }
      add({el.file, el.line, el.column, shown,
           "missing required key '" + shown + "' (meaning: " + k.doc + ")"});
    }
  }

  const Schema& schema_;
  std::string_view text_;
  const std::string& file_;
  const std::vector<std::string>& overrides_;
  Document doc_;
  std::vector<Ranked> ranked_;
  std::set<std::string> invalid_;  // given but refused (shown keys): do not also report as missing
  bool parsed_ = false;
  std::map<std::string, toml::source_region> table_source_;
};

Document validate(const Schema& schema, std::string_view text, const std::string& file_name,
                  const std::vector<std::string>& overrides) {
  return DocumentBuilder(schema, text, file_name, overrides).run();
}

Value validate_live(const Schema& schema, const std::string& key, const std::string& value) {
  const std::string no_file;
  return DocumentBuilder(schema, "", no_file, {}).live_value(trim(key), trim(value));
}

std::string read_scene_text(const std::string& path) {
  const auto cannot = [&](const std::string& why) {
    return SceneError({Issue{path, 0, 0, "", "cannot read scene file: " + why}});
  };
  std::string text, problem;
  if (!read_input_file(path, &text, kMaxTextInputBytes, kTextInputBound, &problem)) throw cannot("it " + problem);
  return text;
}

Document validate_file(const Schema& schema, const std::string& path,
                       const std::vector<std::string>& overrides) {
  return validate(schema, read_scene_text(path), path, overrides);
}

}  // namespace ff::scene
