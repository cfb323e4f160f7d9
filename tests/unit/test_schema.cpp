// Scene-file validation: every kind of bad input gives an Issue with the right file, line, key
// and message; good input gives a Document with defaults filled in; overrides are validated
// like the file; the markdown reference lists every key.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/scene/schema.h"
#include "core/scene/schema_text.h"

namespace ff::scene {
namespace {

Schema test_schema() {
  Schema s;
  s.table("solver", "time integration", true)
      .number("solver.dt", "time step", std::nullopt, Range::positive(), "s")
      .number("solver.t_end", "end time", 1.0, Range::positive(), "s")
      .number("solver.rho_inf", "spectral radius at infinity", 0.8, Range::closed(0, 1))
      .integer("solver.max_iter", "Newton iterations per step", 20, IntRange::at_least(1))
      .boolean("solver.verbose", "log every step", false)
      .choice("solver.kind", "integrator", {"hht", "newmark", "static"}, "hht")
      .table("model", "the flexible body", true)
      .choice("model.kind", "formulation", {"efg", "fem"}, std::nullopt)
      .string("model.name", "label in plots", "beam")
      .integer("model.elements", "number of elements", 8, IntRange::closed(1, 1000))
      .table("model.beam", "beam properties", false)
      .number("model.beam.length", "beam length", std::nullopt, Range::positive(), "m")
      .number("model.beam.damping", "damping ratio", 0.0, Range::right_open(0, 1))
      .number_list("model.beam.gravity", "gravity vector", std::vector<double>{0, 0, -9.81}, {},
                   3, 3, "m/s^2")
      .table("output", "what is written", false)
      .string_list("output.probes", "scalar probes", std::vector<std::string>{"tip"},
                   {"tip", "hub_angle", "energy"})
      .number_list("output.times", "output times", std::vector<double>{}, Range::non_negative(), 0,
                   4, "s");
  return s;
}

const char* kValid =
    "[solver]\n"        // 1
    "dt = 0.01\n"       // 2
    "[model]\n"         // 3
    "kind = \"efg\"\n"; // 4

std::vector<Issue> issues_of(std::string_view text, const std::vector<std::string>& overrides = {}) {
  try {
    validate(test_schema(), text, "scene.toml", overrides);
  } catch (const SceneError& e) {
    return e.issues;
  }
  return {};
}

std::string dump(const std::vector<Issue>& issues) {
  std::string out;
  for (const auto& i : issues) out += "  " + i.to_string() + "\n";
  return out.empty() ? "  (no issues)\n" : out;
}

bool has_issue(const std::vector<Issue>& issues, const std::string& file, int line,
               const std::string& key, const std::string& fragment) {
  for (const auto& i : issues)
    if (i.file == file && i.line == line && i.key == key &&
        i.message.find(fragment) != std::string::npos)
      return true;
  return false;
}

// ---- table of bad inputs --------------------------------------------------------------------

struct BadCase {
  const char* name;
  const char* text;
  int line;
  const char* key;
  const char* fragment;
};

const BadCase kBadCases[] = {
    {"string_for_number", "[solver]\ndt = \"abc\"\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got a string (\"abc\")"},
    {"negative", "[solver]\ndt = -0.5\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got -0.5"},
    {"zero_exclusive_bound", "[solver]\ndt = 0\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got 0"},
    {"closed_range", "[solver]\ndt = 0.1\nrho_inf = 1.5\n[model]\nkind = \"efg\"\n", 3,
     "solver.rho_inf", "expected a number in [0, 1], got 1.5"},
    {"half_open_range", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[model.beam]\nlength = 2\ndamping = 1\n",
     7, "model.beam.damping", "expected a number in [0, 1), got 1"},
    {"infinite", "[solver]\ndt = inf\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a finite number, got inf"},
    {"nan", "[solver]\ndt = nan\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a finite number, got nan"},
    {"float_for_integer", "[solver]\ndt = 0.1\nmax_iter = 2.5\n[model]\nkind = \"efg\"\n", 3,
     "solver.max_iter", "expected an integer >= 1, got a floating-point number (2.5)"},
    {"integral_float_for_integer", "[solver]\ndt = 0.1\nmax_iter = 2.0\n[model]\nkind = \"efg\"\n", 3,
     "solver.max_iter", "got a floating-point number (2.0) (write it without a decimal point)"},
    {"integer_below_min", "[solver]\ndt = 0.1\nmax_iter = 0\n[model]\nkind = \"efg\"\n", 3,
     "solver.max_iter", "expected an integer >= 1, got 0"},
    {"integer_above_max", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\nelements = 1001\n", 5,
     "model.elements", "expected an integer in [1, 1000], got 1001"},
    {"string_for_boolean", "[solver]\ndt = 0.1\nverbose = \"yes\"\n[model]\nkind = \"efg\"\n", 3,
     "solver.verbose", "expected a boolean (true or false), got a string (\"yes\")"},
    {"integer_for_string", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\nname = 3\n", 5,
     "model.name", "expected a string, got an integer (3)"},
    {"bad_choice", "[solver]\ndt = 0.1\n[model]\nkind = \"fe\"\n", 4, "model.kind",
     "expected one of efg, fem, got 'fe' (did you mean 'fem'?)"},
    {"choice_wrong_type", "[solver]\ndt = 0.1\n[model]\nkind = 3\n", 4, "model.kind",
     "expected one of efg, fem, got an integer (3)"},
    {"date_for_number", "[solver]\ndt = 1979-05-27\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got a date"},
    {"list_for_number", "[solver]\ndt = [0.1]\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got a list ("},
    {"table_for_number", "[solver]\ndt = {value = 0.1}\n[model]\nkind = \"efg\"\n", 2, "solver.dt",
     "expected a number > 0, got a table"},
    {"unknown_key_typo", "[solver]\ndt = 0.1\ndtt = 0.2\n[model]\nkind = \"efg\"\n", 3, "solver.dtt",
     "unknown key 'solver.dtt' (did you mean 'solver.dt'?)"},
    {"unknown_key_transposition", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[model.beam]\nlenght = 2\n",
     6, "model.beam.lenght", "unknown key 'model.beam.lenght' (did you mean 'model.beam.length'?)"},
    {"unknown_key_lists_table", "[solver]\ndt = 0.1\nxyz = 1\n[model]\nkind = \"efg\"\n", 3, "solver.xyz",
     "unknown key 'solver.xyz'; keys in [solver] are: dt, t_end, rho_inf, max_iter, verbose, kind"},
    {"key_in_wrong_table", "dt = 0.1\n[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n", 1, "dt",
     "unknown key 'dt' (did you mean 'solver.dt'?)"},
    {"unknown_table", "[solvr]\ndt = 0.1\n[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n", 1, "solvr",
     "unknown key 'solvr' (did you mean 'solver'?)"},
    {"quoted_dotted_key", "\"solver.dt\" = 0.1\n[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n", 1,
     "\"solver.dt\"", "unknown key '\"solver.dt\"'"},
    {"scalar_for_table", "solver = 3\n[model]\nkind = \"efg\"\n", 1, "solver",
     "expected a table [solver] (time integration), got an integer (3)"},
    {"inline_table_value", "solver = { dt = -1.0 }\n[model]\nkind = \"efg\"\n", 1, "solver.dt",
     "expected a number > 0, got -1"},
    {"missing_required_key", "[solver]\ndt = 0.1\n\n[model]\nname = \"x\"\n", 4, "model.kind",
     "missing required key 'model.kind' (meaning: formulation)"},
    {"missing_required_table", "[solver]\ndt = 0.1\n", 0, "model",
     "missing required table [model] (meaning: the flexible body)"},
    {"missing_key_of_optional_table", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[model.beam]\ndamping = 0.1\n",
     5, "model.beam.length", "missing required key 'model.beam.length' (meaning: beam length)"},
    {"list_too_short", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[model.beam]\nlength = 1\ngravity = [0, 0]\n",
     7, "model.beam.gravity", "expected a list of numbers (length 3), got 2 elements"},
    {"list_too_long", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[output]\ntimes = [1, 2, 3, 4, 5]\n",
     6, "output.times", "expected a list of numbers (length 0 to 4), each >= 0, got 5 elements"},
    {"list_element_type", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[model.beam]\nlength = 1\ngravity = [0, \"x\", 0]\n",
     7, "model.beam.gravity", "element [1]: expected a number, got a string (\"x\")"},
    {"list_element_range", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[output]\ntimes = [0.5, -1]\n",
     6, "output.times", "element [1]: expected a number >= 0, got -1"},
    {"scalar_for_list", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[output]\nprobes = \"tip\"\n",
     6, "output.probes", "expected a list of strings, each one of tip, hub_angle, energy, got a string (\"tip\")"},
    {"string_list_bad_element", "[solver]\ndt = 0.1\n[model]\nkind = \"efg\"\n[output]\nprobes = [\"tip\", \"energi\"]\n",
     6, "output.probes",
     "element [1]: expected one of tip, hub_angle, energy, got 'energi' (did you mean 'energy'?)"},
    {"syntax_error", "[solver]\ndt = 0.1\nx = = 3\n[model]\nkind = \"efg\"\n", 3, "", "TOML syntax error"},
    {"syntax_duplicate_key", "[solver]\ndt = 0.1\ndt = 0.2\n[model]\nkind = \"efg\"\n", 3, "",
     "TOML syntax error"},
};

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, ReportsLineKeyAndMessage) {
  const BadCase& c = GetParam();
  const auto issues = issues_of(c.text);
  EXPECT_TRUE(has_issue(issues, "scene.toml", c.line, c.key, c.fragment))
      << "wanted scene.toml:" << c.line << " key '" << c.key << "' containing \"" << c.fragment
      << "\"\ngot:\n"
      << dump(issues);
}

INSTANTIATE_TEST_SUITE_P(Schema, BadInput, ::testing::ValuesIn(kBadCases),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- messages as a whole --------------------------------------------------------------------

TEST(Schema, WhatListsFileLineColumnKeyAndMessage) {
  try {
    validate(test_schema(), "[solver]\ndt = -0.5\n[model]\nkind = \"efg\"\n", "scene.toml");
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "scene.toml:2:6: key 'solver.dt': expected a number > 0, got -0.5");
    ASSERT_EQ(e.issues.size(), 1u);
    EXPECT_EQ(e.issues[0].column, 6);
  }
}

TEST(Schema, CollectsAllIssuesInFileOrder) {
  const char* text =
      "[solver]\n"
      "dt = -1\n"               // 2: range
      "max_iter = 2.5\n"        // 3: type
      "verbos = true\n"         // 4: unknown
      "[model]\n"
      "kind = \"fe\"\n";        // 6: choice
  const auto issues = issues_of(text);
  ASSERT_EQ(issues.size(), 4u) << dump(issues);
  EXPECT_EQ(issues[0].line, 2);
  EXPECT_EQ(issues[1].line, 3);
  EXPECT_EQ(issues[2].line, 4);
  EXPECT_EQ(issues[2].message, "unknown key 'solver.verbos' (did you mean 'solver.verbose'?)");
  EXPECT_EQ(issues[3].line, 6);
  // what() holds one line per issue
  try {
    validate(test_schema(), text, "scene.toml");
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(std::count(what.begin(), what.end(), '\n'), 3);
  }
}

TEST(Schema, RefusedValueIsNotAlsoReportedMissing) {
  const auto issues = issues_of("[solver]\ndt = \"abc\"\n[model]\nkind = \"efg\"\n");
  ASSERT_EQ(issues.size(), 1u) << dump(issues);
}

TEST(Schema, SyntaxErrorIsTheOnlyIssueAndNamesTheLine) {
  const auto issues = issues_of("[solver]\ndt = 0.1\n[model\nkind = \"efg\"\n");
  ASSERT_EQ(issues.size(), 1u) << dump(issues);
  EXPECT_EQ(issues[0].file, "scene.toml");
  EXPECT_EQ(issues[0].line, 3);
  EXPECT_GT(issues[0].column, 0);
  EXPECT_EQ(issues[0].key, "");
}

TEST(Schema, MissingRequiredKeyOfRequiredTableAndEmptyFile) {
  const auto issues = issues_of("");
  EXPECT_TRUE(has_issue(issues, "scene.toml", 0, "solver", "missing required table [solver]")) << dump(issues);
  EXPECT_TRUE(has_issue(issues, "scene.toml", 0, "model", "missing required table [model]")) << dump(issues);
  // keys of a missing table are not reported one by one
  EXPECT_EQ(issues.size(), 2u) << dump(issues);
}

// ---- good input -----------------------------------------------------------------------------

TEST(Schema, DefaultsFilledAndPresenceTracked) {
  const Document d = validate(test_schema(), kValid, "scene.toml");
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.01);
  EXPECT_DOUBLE_EQ(d.number("solver.t_end"), 1.0);
  EXPECT_DOUBLE_EQ(d.number("solver.rho_inf"), 0.8);
  EXPECT_EQ(d.integer("solver.max_iter"), 20);
  EXPECT_FALSE(d.boolean("solver.verbose"));
  EXPECT_EQ(d.string("solver.kind"), "hht");
  EXPECT_EQ(d.string("model.kind"), "efg");
  EXPECT_EQ(d.string("model.name"), "beam");
  EXPECT_EQ(d.numbers("model.beam.gravity"), (std::vector<double>{0, 0, -9.81}));
  EXPECT_EQ(d.strings("output.probes"), (std::vector<std::string>{"tip"}));
  EXPECT_TRUE(d.numbers("output.times").empty());

  EXPECT_TRUE(d.present("solver.dt"));
  EXPECT_FALSE(d.present("solver.t_end"));
  EXPECT_EQ(d.where("solver.dt"), "scene.toml:2:6");
  EXPECT_EQ(d.where("model.kind"), "scene.toml:4:8");
  EXPECT_EQ(d.where("solver.t_end"), "default");

  EXPECT_TRUE(d.table_present(""));
  EXPECT_TRUE(d.table_present("solver"));
  EXPECT_FALSE(d.table_present("model.beam"));
  EXPECT_FALSE(d.table_present("output"));
  // required key of an absent optional table: no value, and reading it is a programming error
  EXPECT_FALSE(d.present("model.beam.length"));
  EXPECT_EQ(d.where("model.beam.length"), "absent");
  EXPECT_THROW(d.number("model.beam.length"), std::logic_error);
  EXPECT_DOUBLE_EQ(d.number("model.beam.damping"), 0.0);  // its defaults are still there

  EXPECT_EQ(d.text(), kValid);
  EXPECT_EQ(d.value_text("solver.dt"), "0.01");
  EXPECT_EQ(d.value_text("solver.t_end"), "1.0");
  EXPECT_EQ(d.value_text("model.kind"), "\"efg\"");
  EXPECT_EQ(d.value_text("model.beam.gravity"), "[0.0, 0.0, -9.81]");
  EXPECT_EQ(d.key_paths().size(), test_schema().keys().size());
}

TEST(Schema, IssueAtKeyForChecksAcrossKeys) {
  const Document d = validate(test_schema(), kValid, "scene.toml", {"solver.t_end=0.001"});
  const Issue from_file = d.issue("solver.dt", "must be smaller than solver.t_end");
  EXPECT_EQ(from_file.to_string(), "scene.toml:2:6: key 'solver.dt': must be smaller than solver.t_end");
  EXPECT_EQ(d.issue("solver.t_end", "x").file, "--set solver.t_end=0.001");
  EXPECT_EQ(d.issue("solver.rho_inf", "x").to_string(), "scene.toml: key 'solver.rho_inf': x");
  EXPECT_THROW(d.issue("solver.nope", "x"), std::logic_error);
}

TEST(Schema, IntegersAcceptedAsNumbers) {
  const Document d = validate(test_schema(),
                              "[solver]\ndt = 2\n[model]\nkind = \"fem\"\n"
                              "[model.beam]\nlength = 3\ngravity = [0, 0, -10]\n",
                              "scene.toml");
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 2.0);
  EXPECT_DOUBLE_EQ(d.number("model.beam.length"), 3.0);
  EXPECT_EQ(d.numbers("model.beam.gravity"), (std::vector<double>{0.0, 0.0, -10.0}));
  EXPECT_TRUE(d.table_present("model.beam"));
}

TEST(Schema, DottedAndInlineTablesAccepted) {
  const Document d = validate(test_schema(),
                              "solver.dt = 0.5\nmodel = { kind = \"fem\", beam = { length = 2.0 } }\n",
                              "scene.toml");
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.5);
  EXPECT_DOUBLE_EQ(d.number("model.beam.length"), 2.0);
  EXPECT_TRUE(d.table_present("model.beam"));
}

TEST(Schema, LookupMistakesAreLogicErrors) {
  const Document d = validate(test_schema(), kValid, "scene.toml");
  EXPECT_THROW(d.number("solver.dtt"), std::logic_error);
  EXPECT_THROW(d.integer("solver.dt"), std::logic_error);   // wrong accessor
  EXPECT_THROW(d.number("solver.max_iter"), std::logic_error);
  EXPECT_THROW(d.present("solver"), std::logic_error);      // a table, not a key
  EXPECT_THROW(d.table_present("solver.dt"), std::logic_error);
  EXPECT_THROW(d.where("nope"), std::logic_error);
}

// ---- overrides ------------------------------------------------------------------------------

TEST(Schema, OverridesValid) {
  const Document d = validate(test_schema(), kValid, "scene.toml",
                              {"solver.dt=0.02", "model.kind=fem", "solver.verbose=true",
                               "model.name=\"my beam\"", "solver.max_iter = 7",
                               "model.beam.gravity=[0, -9.81, 0]", "model.beam.length=2",
                               "output.probes=[\"tip\", \"energy\"]"});
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.02);
  EXPECT_EQ(d.where("solver.dt"), "--set solver.dt=0.02");
  EXPECT_TRUE(d.present("solver.dt"));
  EXPECT_EQ(d.string("model.kind"), "fem");  // bare word taken as a string
  EXPECT_TRUE(d.boolean("solver.verbose"));
  EXPECT_EQ(d.string("model.name"), "my beam");
  EXPECT_EQ(d.integer("solver.max_iter"), 7);
  EXPECT_EQ(d.numbers("model.beam.gravity"), (std::vector<double>{0, -9.81, 0}));
  EXPECT_DOUBLE_EQ(d.number("model.beam.length"), 2.0);
  EXPECT_TRUE(d.table_present("model.beam"));  // given by --set
  EXPECT_TRUE(d.table_present("output"));
  EXPECT_EQ(d.strings("output.probes"), (std::vector<std::string>{"tip", "energy"}));
  // a string key takes the raw text even when it looks like another TOML type
  EXPECT_EQ(validate(test_schema(), kValid, "scene.toml", {"model.name=2024"}).string("model.name"), "2024");
  EXPECT_EQ(validate(test_schema(), kValid, "scene.toml", {"model.name=true"}).string("model.name"), "true");
  // an empty value is a valid plain string
  EXPECT_EQ(validate(test_schema(), kValid, "scene.toml", {"model.name="}).string("model.name"), "");
}

TEST(Schema, OverrideSuppliesMissingRequiredKey) {
  const Document d = validate(test_schema(), "[solver]\n[model]\nkind = \"efg\"\n", "scene.toml",
                              {"solver.dt=0.01"});
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.01);
}

TEST(Schema, OverrideIntoOptionalTableRequiresItsKeys) {
  const auto issues = issues_of(kValid, {"model.beam.damping=0.1"});
  EXPECT_TRUE(has_issue(issues, "scene.toml", 0, "model.beam.length",
                        "missing required key 'model.beam.length'"))
      << dump(issues);
}

struct OverrideCase {
  const char* name;
  const char* arg;
  const char* key;
  const char* fragment;
};

const OverrideCase kBadOverrides[] = {
    {"wrong_type", "solver.dt=abc", "solver.dt", "expected a number > 0, got a string (\"abc\")"},
    {"out_of_range", "solver.rho_inf=2", "solver.rho_inf", "expected a number in [0, 1], got 2"},
    {"negative", "solver.dt=-0.5", "solver.dt", "expected a number > 0, got -0.5"},
    {"float_for_integer", "solver.max_iter=3.5", "solver.max_iter", "expected an integer >= 1"},
    {"boolean_word", "solver.verbose=yes", "solver.verbose",
     "expected a boolean (true or false), got a string (\"yes\")"},
    {"bad_choice", "model.kind=fe", "model.kind", "expected one of efg, fem, got 'fe'"},
    {"number_for_choice", "model.kind=3", "model.kind", "expected one of efg, fem, got '3'"},
    {"unknown_key", "solver.dtt=0.1", "solver.dtt", "unknown key 'solver.dtt' (did you mean 'solver.dt'?)"},
    {"unknown_table", "solvr.dt=0.1", "solvr.dt", "unknown key 'solvr.dt' (did you mean 'solver.dt'?)"},
    {"unknown_deep", "model.bem.length=1", "model.bem.length",
     "unknown key 'model.bem.length' (did you mean 'model.beam.length'?)"},
    {"no_equals_known_key", "solver.dt", "solver.dt", "missing '=value': write --set solver.dt=VALUE"},
    {"no_equals", "verbose", "", "expected the form key=value"},
    {"empty_key", "=3", "", "the key before '=' is empty"},
    {"empty_value", "model.beam.length=", "model.beam.length",
     "no value after '=': write --set model.beam.length=VALUE, VALUE being a number"},
    {"table_not_key", "solver=3", "solver", "'solver' is a table; --set needs a key inside it"},
    {"invalid_toml_list", "model.beam.gravity=[1, 2", "model.beam.gravity", "is not valid TOML"},
    {"list_length", "model.beam.gravity=[1, 2]", "model.beam.gravity",
     "expected a list of numbers (length 3), got 2 elements"},
    {"injection_is_one_string", "solver.dt=1\nsolver.t_end = -1", "solver.dt", "expected a number > 0, got a string"},
};

class BadOverride : public ::testing::TestWithParam<OverrideCase> {};

TEST_P(BadOverride, NamesTheSetArgument) {
  const OverrideCase& c = GetParam();
  const auto issues = issues_of(kValid, {c.arg});
  EXPECT_TRUE(has_issue(issues, std::string("--set ") + c.arg, 0, c.key, c.fragment))
      << "wanted '--set " << c.arg << "' key '" << c.key << "' containing \"" << c.fragment
      << "\"\ngot:\n"
      << dump(issues);
  EXPECT_EQ(issues.size(), 1u) << dump(issues);
}

INSTANTIATE_TEST_SUITE_P(Schema, BadOverride, ::testing::ValuesIn(kBadOverrides),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Schema, OverrideIssueFormat) {
  try {
    validate(test_schema(), kValid, "scene.toml", {"solver.dt=-0.5"});
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "--set solver.dt=-0.5: key 'solver.dt': expected a number > 0, got -0.5");
  }
}

TEST(Schema, OverridesCheckedEvenAfterSyntaxError) {
  const auto issues = issues_of("[solver\n", {"solver.dtt=1"});
  ASSERT_EQ(issues.size(), 2u) << dump(issues);
  EXPECT_EQ(issues[0].line, 1);
  EXPECT_EQ(issues[1].file, "--set solver.dtt=1");
}

// ---- files ----------------------------------------------------------------------------------

TEST(Schema, ValidateFileReadsAndNamesTheFile) {
  const auto path = std::filesystem::temp_directory_path() / "ff_test_schema_scene.toml";
  {
    std::ofstream out(path);
    out << "[solver]\ndt = 0.25\n[model]\nkind = \"fem\"\n";
  }
  const Document d = validate_file(test_schema(), path.string());
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.25);
  EXPECT_EQ(d.where("solver.dt"), path.string() + ":2:6");
  {
    std::ofstream out(path);
    out << "[solver]\ndt = 0\n[model]\nkind = \"fem\"\n";
  }
  try {
    validate_file(test_schema(), path.string());
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    ASSERT_EQ(e.issues.size(), 1u);
    EXPECT_EQ(e.issues[0].file, path.string());
    EXPECT_EQ(e.issues[0].line, 2);
  }
  std::filesystem::remove(path);
}

TEST(Schema, UnreadableFileIsASceneError) {
  try {
    validate_file(test_schema(), "/nonexistent/dir/scene.toml");
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    ASSERT_EQ(e.issues.size(), 1u);
    EXPECT_EQ(e.issues[0].file, "/nonexistent/dir/scene.toml");
    EXPECT_NE(e.issues[0].message.find("cannot read scene file"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/scene.toml"), std::string::npos);
  }
  try {
    validate_file(test_schema(), std::filesystem::temp_directory_path().string());
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_NE(e.issues.at(0).message.find("directory"), std::string::npos);
  }
}

// ---- the schema itself ----------------------------------------------------------------------

TEST(Schema, BadDeclarationsAreLogicErrors) {
  Schema s;
  s.table("a", "table a");
  EXPECT_THROW(s.number("b.x", "undeclared table", 1.0), std::logic_error);
  EXPECT_THROW(s.number("a.x", "", 1.0), std::logic_error);
  EXPECT_THROW(s.number("a.x", "default out of range", -1.0, Range::positive()), std::logic_error);
  EXPECT_THROW(s.integer("a.n", "default out of range", 0, IntRange::at_least(1)), std::logic_error);
  EXPECT_THROW(s.choice("a.c", "default not a choice", {"p", "q"}, "r"), std::logic_error);
  EXPECT_THROW(s.number_list("a.l", "default too short", std::vector<double>{1}, {}, 2, 2),
               std::logic_error);
  EXPECT_THROW(s.number("a.bad key", "not a bare key", 1.0), std::logic_error);
  s.number("a.x", "fine", 1.0);
  EXPECT_THROW(s.number("a.x", "declared twice", 1.0), std::logic_error);
  EXPECT_THROW(s.table("a.x", "key and table", false), std::logic_error);
}

TEST(Schema, RangeText) {
  EXPECT_EQ(Range::positive().text(), "> 0");
  EXPECT_EQ(Range::at_least(2).text(), ">= 2");
  EXPECT_EQ(Range::less_than(5).text(), "< 5");
  EXPECT_EQ(Range::left_open(0, 1).text(), "(0, 1]");
  EXPECT_EQ(Range::closed(0.5, 1e-3 * 2000).text(), "[0.5, 2]");
  EXPECT_EQ(Range{}.text(), "any");
  EXPECT_EQ(IntRange::closed(1, 10).text(), "[1, 10]");
  EXPECT_TRUE(Range::left_open(0, 1).contains(1.0));
  EXPECT_FALSE(Range::left_open(0, 1).contains(0.0));
}

TEST(Schema, SuggestionsOnlyForPlausibleTypos) {
  EXPECT_EQ(text::closest("dtt", {"dt", "t_end"}), "dt");
  EXPECT_EQ(text::closest("lenght", {"length", "damping"}), "length");
  EXPECT_EQ(text::closest("DT", {"dt"}), "dt");
  EXPECT_EQ(text::closest("xyz", {"dt", "t_end", "kind"}), "");
  EXPECT_EQ(text::closest("a", {"dt"}), "");
  EXPECT_EQ(text::edit_distance("kitten", "sitting"), 3u);
}

TEST(Schema, MarkdownReferenceListsEveryTableAndKey) {
  const Schema s = test_schema();
  const std::string md = s.markdown_reference();
  for (const auto& k : s.keys()) {
    EXPECT_NE(md.find("| `" + k.path + "` |"), std::string::npos) << k.path;
    EXPECT_NE(md.find(k.doc), std::string::npos) << k.path;
  }
  for (const auto& t : s.tables()) {
    if (t.path.empty()) continue;
    EXPECT_NE(md.find("### `[" + t.path + "]`"), std::string::npos) << t.path;
  }
  EXPECT_NE(md.find("| key | type | default | allowed | meaning |"), std::string::npos);
  EXPECT_NE(md.find("| `solver.dt` | number [s] | **required** | > 0 | time step |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `solver.kind` | choice | `\"hht\"` | `hht`, `newmark`, `static` | integrator |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `model.beam.gravity` | list of numbers [m/s^2] | `[0.0, 0.0, -9.81]` | length 3 | gravity vector |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `output.times` | list of numbers [s] | `[]` | length 0 to 4; each >= 0 | output times |"),
            std::string::npos)
      << md;
  // tables appear in declaration order
  EXPECT_LT(md.find("[solver]"), md.find("[model]"));
  EXPECT_LT(md.find("[model]"), md.find("[model.beam]"));
}

}  // namespace
}  // namespace ff::scene
