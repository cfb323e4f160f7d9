#pragma once
/// \file schema.h
/// Scene-file validation: one declared Schema of every key a scene may hold, checked against a
/// TOML text plus command-line overrides (`--set solver.dt=0.01`), giving a Document of
/// validated values with defaults filled in. The same Schema renders the markdown reference of
/// keys (docs/reference/scene-keys.md), so code, messages and docs cannot drift apart.
///
/// Contract:
///  - Bad *input* (the scene file or an override) never crashes and never silently defaults:
///    validate() collects every Issue (file, line, column, key, what was expected and what was
///    given) and throws one SceneError. The caller prints what() and exits non-zero.
///  - Bad *programming* (a malformed declaration, a default outside its own range, a lookup of
///    an undeclared path or with the wrong type) throws std::logic_error.
///
/// Paths are dotted TOML bare keys ("solver.dt"); the root table is the empty path "".
/// Every key lives in a declared table; tables nest (declare "model" before "model.beam").
/// A key without a default is required whenever its table is present in the input; a required
/// table is required whenever its parent is present (the root always is).
///
/// Arrays of tables: table_array("bc", ...) declares that `[[bc]]` may appear any number of times
/// (within min_count..max_count, checked whenever the parent table is present), written either as
/// `[[bc]]` headers or as an inline array of inline tables `bc = [{ type = "fix" }, ...]`.
/// Keys of an element are declared with the array's path as prefix ("bc.type"); defaults and
/// required keys apply to each element. Issues name the element: key 'bc[2].type'. Elements hold
/// plain keys only: tables nested in an element are neither declarable nor accepted. Read the
/// values with the indexed accessors (`doc.count("bc")`, `doc.string("bc.type", i)`); the
/// non-indexed accessors refuse keys of arrays and vice versa. `--set bc[1].type=fix` changes a key
/// of an element the file already has.
///
/// Example:
/// \code
///   Schema s;
///   s.table("solver", "time integration", /*required=*/true)
///    .number("solver.dt", "time step", std::nullopt, Range::positive(), "s")
///    .choice("solver.kind", "integrator", {"hht", "newmark"}, "hht");
///   Document d = validate_file(s, "scene.toml", {"solver.dt=0.01"});
///   double dt = d.number("solver.dt");
/// \endcode

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/scene/schema_value.h"

namespace ff::scene {

/// One problem found in the input.
struct Issue {
  std::string file;     ///< scene file name, or "--set key=value" for an override
  int line = 0;         ///< 1-based; 0 when no line applies (missing table, override)
  int column = 0;       ///< 1-based; 0 when no column applies
  std::string key;      ///< dotted path of the offending key; empty for syntax errors
  std::string message;  ///< what was expected and what was given

  /// "file:line:column: key 'solver.dt': expected a number > 0, got -0.5"
  /// (":line:column" left out when line is 0, "key '...': " left out when key is empty).
  std::string to_string() const;
};

/// Thrown by validate() when the input has any issue; what() lists all, one per line.
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(std::vector<Issue> issues);
  std::vector<Issue> issues;
};

/// Allowed interval of a floating-point number; unset bounds are open-ended.
/// Rendered as "> 0", ">= 2", "<= 5", "(0, 1]" etc. in messages and in the reference.
struct Range {
  std::optional<double> min, max;
  bool min_inclusive = true;
  bool max_inclusive = true;

  static Range positive() { return greater_than(0.0); }     ///< > 0
  static Range non_negative() { return at_least(0.0); }     ///< >= 0
  static Range at_least(double lo) { return {lo, std::nullopt, true, true}; }
  static Range greater_than(double lo) { return {lo, std::nullopt, false, true}; }
  static Range at_most(double hi) { return {std::nullopt, hi, true, true}; }
  static Range less_than(double hi) { return {std::nullopt, hi, true, false}; }
  static Range closed(double lo, double hi) { return {lo, hi, true, true}; }        ///< [lo, hi]
  static Range open(double lo, double hi) { return {lo, hi, false, false}; }        ///< (lo, hi)
  static Range left_open(double lo, double hi) { return {lo, hi, false, true}; }    ///< (lo, hi]
  static Range right_open(double lo, double hi) { return {lo, hi, true, false}; }   ///< [lo, hi)

  bool contains(double x) const;
  bool unbounded() const { return !min && !max; }
  /// "> 0", "(0, 1]", ... ; "any" when unbounded.
  std::string text() const;
};

/// Allowed interval of an integer, both bounds inclusive; unset bounds are open-ended.
struct IntRange {
  std::optional<long long> min, max;

  static IntRange at_least(long long lo) { return {lo, std::nullopt}; }
  static IntRange at_most(long long hi) { return {std::nullopt, hi}; }
  static IntRange closed(long long lo, long long hi) { return {lo, hi}; }

  bool contains(long long x) const;
  bool unbounded() const { return !min && !max; }
  /// ">= 1", "[1, 10]", ... ; "any" when unbounded.
  std::string text() const;
};

/// The declared set of tables and keys.
class Schema {
 public:
  struct TableSpec {
    std::string path;
    std::string doc;
    bool required = false;                ///< plain tables; arrays use min_count instead
    bool array = false;                   ///< an array of tables [[path]] (see table_array)
    std::size_t min_count = 0;            ///< arrays: allowed number of elements
    std::size_t max_count = SIZE_MAX;
  };
  struct KeySpec {
    std::string path;
    std::string doc;
    Kind kind = Kind::Number;
    Value default_value;                  ///< monostate = required
    Range range;                          ///< Number, and each element of NumberList
    IntRange int_range;                   ///< Integer
    std::string unit;                     ///< Number / NumberList, "" for none
    std::vector<std::string> choices;     ///< Choice; StringList allowed values (empty = any)
    std::size_t min_len = 0;              ///< lists
    std::size_t max_len = SIZE_MAX;       ///< lists
    bool live = false;                    ///< may change while a run goes on (see live())
    /// The key means something only while a sibling choice key (`condition_key`, a full path such
    /// as "part.generator") has one of `condition_values` (see applies_when()); "" = always.
    std::string condition_key;
    std::vector<std::string> condition_values;
    bool required() const { return std::holds_alternative<std::monostate>(default_value); }
    /// Whether the key applies when its condition key has the value `condition_value`.
    bool applies(const std::string& condition_value) const;
  };

  /// A table; `doc` is its one-line meaning. Its parent table must be declared first.
  /// Tables cannot be declared inside an array of tables.
  Schema& table(std::string path, std::string doc, bool required = false);
  /// An array of tables `[[path]]` with min_count <= number of elements <= max_count (checked when
  /// its parent table is present; min_count >= 1 makes it required). Its parent must be a declared
  /// plain table; declare its keys afterwards as "path.key".
  Schema& table_array(std::string path, std::string doc, std::size_t min_count = 0,
                      std::size_t max_count = SIZE_MAX);
  /// A floating-point number (integers in the input are accepted and converted). Non-finite
  /// values (inf, nan) are always refused.
  Schema& number(std::string path, std::string doc, std::optional<double> default_value,
                 Range range = {}, std::string unit = "");
  /// An integer (a floating-point value in the input is refused, even 2.0).
  Schema& integer(std::string path, std::string doc, std::optional<long long> default_value,
                  IntRange range = {});
  Schema& boolean(std::string path, std::string doc, std::optional<bool> default_value);
  Schema& string(std::string path, std::string doc, std::optional<std::string> default_value);
  /// A string that must be one of `choices` (read it back with Document::string()).
  Schema& choice(std::string path, std::string doc, std::vector<std::string> choices,
                 std::optional<std::string> default_value);
  /// An array of numbers, each within `each`, with min_len <= length <= max_len.
  Schema& number_list(std::string path, std::string doc,
                      std::optional<std::vector<double>> default_value, Range each = {},
                      std::size_t min_len = 0, std::size_t max_len = SIZE_MAX,
                      std::string unit = "");
  /// An array of strings, each one of `allowed` (empty = any string).
  Schema& string_list(std::string path, std::string doc,
                      std::optional<std::vector<std::string>> default_value,
                      std::vector<std::string> allowed = {});

  /// Marks the declared key `path` (outside arrays of tables) as live: it may change while a run
  /// goes on (the GUI's `set`), through validate_live() and Simulation::change_live, instead of
  /// rebuilding the model. The model's change_live must accept it.
  Schema& live(std::string_view path);
  /// The live keys, in declaration order.
  std::vector<std::string> live_keys() const;

  /// Sets the unit of the declared number or number-list key `path` ("length", "force/length^2"
  /// for a structure in consistent units), shown beside its value in the reference and the window.
  Schema& unit_of(std::string_view path, std::string unit);

  /// Declares that the key `path` applies only while the choice key `condition_key` of the same
  /// table has one of `values` (a generator's dimensions, a selector's point): editors list it
  /// only then, and drop it when the choice changes to a value it does not serve.
  Schema& applies_when(std::string_view path, std::string condition_key, std::vector<std::string> values);

  /// A key (or a whole table) that a newer vocabulary renamed: input that still uses `old_path`
  /// is refused at its line with "renamed to 'new_path'" instead of a bare "unknown key".
  Schema& renamed(std::string old_path, std::string new_path);
  /// The new name of a renamed key or table (the longest renamed prefix of `path` carries its
  /// rest along), or "" when `path` was not renamed.
  std::string renamed_to(std::string_view path) const;
  const std::map<std::string, std::string>& renames() const { return renamed_; }

  /// Markdown reference of every table and key, in declaration order, one section per table:
  /// | key | type | default | allowed | meaning |
  /// Arrays of tables get a section "### [[bc]] (array of tables, 0 or more)" with their keys.
  std::string markdown_reference() const;

  /// Plain tables and arrays of tables (TableSpec::array), in declaration order.
  const std::vector<TableSpec>& tables() const { return tables_; }
  const std::vector<KeySpec>& keys() const { return keys_; }
  /// nullptr when `path` is not a declared table (plain or array) / key. The root "" is always a
  /// table.
  const TableSpec* find_table(std::string_view path) const;
  const KeySpec* find_key(std::string_view path) const;
  /// nullptr unless `path` is a declared array of tables.
  const TableSpec* find_array(std::string_view path) const;
  /// The array of tables a key belongs to ("bc" for "bc.type"); "" for a key outside arrays.
  std::string array_of(std::string_view key_path) const;
  /// Names (last path segment) of the tables, arrays and keys declared directly inside
  /// `table_path` (a table or an array).
  std::vector<std::string> children(std::string_view table_path) const;

 private:
  Schema& add_key(KeySpec spec);
  void check_new_path(const std::string& path, const std::string& doc) const;

  std::vector<TableSpec> tables_{TableSpec{"", "top level", true}};
  std::vector<KeySpec> keys_;
  std::map<std::string, std::string> renamed_;  // old path -> new path
};

/// Validated values of one scene, defaults filled in. Independent of the Schema's lifetime.
/// Every lookup of an undeclared path, of a key with the wrong accessor (number() on an
/// integer key), or of a required key whose table is absent throws std::logic_error.
/// Keys of an array of tables are read only with the indexed overloads, `index` counting the
/// elements from 0 in file order; a non-indexed lookup of such a key, an indexed lookup of a key
/// outside arrays, or an index >= count() throws std::logic_error.
class Document {
 public:
  double number(const std::string& path) const;
  long long integer(const std::string& path) const;
  bool boolean(const std::string& path) const;
  const std::string& string(const std::string& path) const;  ///< string and choice keys
  std::vector<double> numbers(const std::string& path) const;
  std::vector<std::string> strings(const std::string& path) const;

  /// The key was given in the file or by --set (not just defaulted).
  bool present(const std::string& path) const;
  /// The table was given in the file (header, dotted key or inline) or by a --set inside it.
  /// The root "" is always present.
  bool table_present(const std::string& path) const;
  /// "file:line:col", "--set key=value", "default", or "absent" (optional table not given).
  std::string where(const std::string& path) const;
  /// An Issue located where `path` got its value (file:line:column, the --set argument, or the
  /// file with no line for a default), for checks across keys made after validation, e.g.
  /// `throw SceneError({doc.issue("solver.t_end", "must exceed solver.dt")})`.
  Issue issue(const std::string& path, std::string message) const;
  /// The value as TOML text ("0.01", "\"efg\"", "[1.0, 2.0]"); "" when absent.
  /// Meant for logging the effective settings (RunInfo::settings).
  std::string value_text(const std::string& path) const;
  /// Every declared key path outside arrays of tables, in declaration order.
  const std::vector<std::string>& key_paths() const { return order_; }

  // ---- arrays of tables -----------------------------------------------------------------------

  /// The schema declares `array_path` as an array of tables (count() may be asked).
  bool declares_array(const std::string& array_path) const { return arrays_.count(array_path) != 0; }
  /// Number of elements of the array of tables `array_path` (0 when absent).
  std::size_t count(const std::string& array_path) const;
  double number(const std::string& path, std::size_t index) const;
  long long integer(const std::string& path, std::size_t index) const;
  bool boolean(const std::string& path, std::size_t index) const;
  const std::string& string(const std::string& path, std::size_t index) const;
  std::vector<double> numbers(const std::string& path, std::size_t index) const;
  std::vector<std::string> strings(const std::string& path, std::size_t index) const;
  /// The key was given in element `index` (file or --set), not just defaulted.
  bool present(const std::string& path, std::size_t index) const;
  /// "file:line:col", "--set bc[1].type=fix" or "default".
  std::string where(const std::string& path, std::size_t index) const;
  /// An Issue with key "bc[index].type", located at the key's value, its --set argument, or (for
  /// a defaulted key) the element's header line.
  Issue issue(const std::string& path, std::size_t index, std::string message) const;
  std::string value_text(const std::string& path, std::size_t index) const;
  /// Every declared array of tables, in declaration order.
  const std::vector<std::string>& array_paths() const { return array_order_; }
  /// The declared key paths of one array ("bc.type", ...), in declaration order.
  std::vector<std::string> element_key_paths(const std::string& array_path) const;

  const std::string& text() const { return text_; }            ///< original file text
  const std::string& file_name() const { return file_name_; }  ///< as given to validate()

 private:
  friend class DocumentBuilder;
  struct Entry {
    Kind kind = Kind::Number;
    Value value;
    bool present = false;
    std::string where = "absent";
    std::string file;  ///< file name or "--set ..." when present
    int line = 0, column = 0;
    std::string array;  ///< the array of tables holding this key; "" outside arrays
  };
  /// One element of an array of tables: where it starts and its keys' values.
  struct Element {
    std::string file;
    int line = 0, column = 0;
    std::map<std::string, Entry, std::less<>> entries;
  };
  struct Array {
    std::vector<Element> elements;
    std::vector<std::string> keys;  ///< declared key paths, in declaration order
  };
  const Entry& entry(const std::string& path, std::initializer_list<Kind> kinds,
                     const char* accessor) const;
  const Element& element(const std::string& path, std::size_t index, const char* accessor) const;
  const Entry& entry(const std::string& path, std::size_t index, std::initializer_list<Kind> kinds,
                     const char* accessor) const;

  std::map<std::string, Entry, std::less<>> entries_;  ///< every key; element keys as templates
  std::map<std::string, bool, std::less<>> tables_;
  std::map<std::string, Array, std::less<>> arrays_;
  std::vector<std::string> order_;
  std::vector<std::string> array_order_;
  std::string text_;
  std::string file_name_;
};

/// Parses `text` as TOML (syntax errors reported with file:line:column), applies `overrides`
/// ("key=value"; value parsed as a TOML value such as 0.01, true, "str", [1, 2]; a bare word
/// that is not valid TOML is taken as a string, so `model.kind=efg` works), validates
/// everything against `schema`, and throws SceneError listing ALL issues if there is any.
/// An override replaces the file's value; its issues name "--set key=value" as the file.
/// `--set bc[1].type=fix` sets a key of element 1 of the array of tables [[bc]], which the file
/// must already have; a whole array cannot be set.
Document validate(const Schema& schema, std::string_view text, const std::string& file_name,
                  const std::vector<std::string>& overrides = {});

/// The value of a live edit `key=value` (the GUI's `set` while a run goes on): `value` is read as
/// --set reads it (TOML value syntax; a bare word is a string) and checked by the same code as a
/// scene file value, so types, ranges and messages are those of a scene file. Never monostate.
/// Throws SceneError with one Issue naming the key (its file is "live key=value") when the value
/// does not validate, or when `key` is not declared live (the message lists the live keys).
Value validate_live(const Schema& schema, const std::string& key, const std::string& value);

/// The contents of the scene file `path`; a SceneError naming it when it cannot be read, or is not a
/// regular file or larger than kMaxTextInputBytes (core/frame/input_file.h).
std::string read_scene_text(const std::string& path);

/// validate() on the contents of `path`; an unreadable file is a SceneError naming it.
Document validate_file(const Schema& schema, const std::string& path,
                       const std::vector<std::string>& overrides = {});

}  // namespace ff::scene
