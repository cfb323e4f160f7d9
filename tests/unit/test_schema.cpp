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

// A renamed key or table is refused at its own line with its new name, not "unknown key".
TEST(Schema, RenamedKeyAndTableNameTheirNewPlace) {
  Schema s = test_schema();
  s.renamed("solver.end_time", "solver.t_end").renamed("time.dt", "solver.dt").renamed("integrator", "solver");
  EXPECT_EQ(s.renamed_to("integrator.rho_inf"), "solver.rho_inf");
  EXPECT_EQ(s.renamed_to("solver.dt"), "");
  std::vector<Issue> got;
  try {
    validate(s, "[solver]\nend_time = 2.0\n[time]\ndt = 0.1\n[model]\nkind = \"efg\"\n[integrator]\nrho_inf = 0.5\n",
             "scene.toml", {});
  } catch (const SceneError& e) {
    got = e.issues;
  }
  EXPECT_TRUE(has_issue(got, "scene.toml", 2, "solver.end_time", "was renamed to 'solver.t_end'")) << dump(got);
  EXPECT_TRUE(has_issue(got, "scene.toml", 4, "time.dt", "was renamed to 'solver.dt'")) << dump(got);
  EXPECT_TRUE(has_issue(got, "scene.toml", 7, "integrator", "was renamed to 'solver'")) << dump(got);
}

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

// ---- arrays of tables -----------------------------------------------------------------------

Schema array_schema() {
  Schema s;
  s.table("solver", "time integration", true)
      .number("solver.dt", "time step", std::nullopt, Range::positive(), "s")
      .table_array("bc", "boundary conditions")
      .choice("bc.type", "kind of support", {"clamped", "hinged", "symmetry", "fix"}, std::nullopt)
      .string("bc.nodes", "node set", std::nullopt)
      .number("bc.value", "prescribed value", 0.0, Range::non_negative())
      .integer("bc.order", "derivative order", 1, IntRange::closed(1, 3))
      .boolean("bc.active", "applied at all", true)
      .number_list("bc.point", "reference point", std::vector<double>{0, 0, 0}, {}, 3, 3, "m")
      .string_list("bc.dofs", "restrained dofs", std::vector<std::string>{"x", "y", "z"},
                   {"x", "y", "z", "rx", "ry", "rz"})
      .table_array("load", "applied loads", 1, 2)
      .number("load.magnitude", "load magnitude", std::nullopt, Range::positive(), "N")
      .table("model", "the body", false)
      .string("model.name", "label", "body")
      .table_array("model.layers", "laminate layers", 0, 3)
      .number("model.layers.thickness", "layer thickness", 0.001, Range::positive(), "m");
  return s;
}

const char* kValidArrays =
    "[solver]\n"            // 1
    "dt = 0.01\n"           // 2
    "\n"                    // 3
    "[[bc]]\n"              // 4
    "type = \"clamped\"\n"  // 5
    "nodes = \"root\"\n"    // 6
    "\n"                    // 7
    "[[bc]]\n"              // 8
    "type = \"hinged\"\n"   // 9
    "nodes = \"tip\"\n"     // 10
    "value = 2.5\n"         // 11
    "point = [1, 2, 3]\n"   // 12
    "\n"                    // 13
    "[[load]]\n"            // 14
    "magnitude = 10\n";     // 15

std::vector<Issue> array_issues(std::string_view text, const std::vector<std::string>& overrides = {}) {
  try {
    validate(array_schema(), text, "scene.toml", overrides);
  } catch (const SceneError& e) {
    return e.issues;
  }
  return {};
}

TEST(SchemaArrays, ValidArraysWithDefaultsPerElement) {
  const Document d = validate(array_schema(), kValidArrays, "scene.toml");
  ASSERT_EQ(d.count("bc"), 2u);
  EXPECT_EQ(d.count("load"), 1u);
  EXPECT_EQ(d.count("model.layers"), 0u);
  EXPECT_FALSE(d.table_present("model"));

  EXPECT_EQ(d.string("bc.type", 0), "clamped");
  EXPECT_EQ(d.string("bc.type", 1), "hinged");
  EXPECT_EQ(d.string("bc.nodes", 1), "tip");
  EXPECT_DOUBLE_EQ(d.number("bc.value", 0), 0.0);  // default in element 0
  EXPECT_DOUBLE_EQ(d.number("bc.value", 1), 2.5);  // given in element 1
  EXPECT_EQ(d.integer("bc.order", 1), 1);
  EXPECT_TRUE(d.boolean("bc.active", 0));
  EXPECT_EQ(d.numbers("bc.point", 0), (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(d.numbers("bc.point", 1), (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(d.strings("bc.dofs", 1), (std::vector<std::string>{"x", "y", "z"}));
  EXPECT_DOUBLE_EQ(d.number("load.magnitude", 0), 10.0);

  EXPECT_FALSE(d.present("bc.value", 0));
  EXPECT_TRUE(d.present("bc.value", 1));
  EXPECT_EQ(d.where("bc.type", 0), "scene.toml:5:8");
  EXPECT_EQ(d.where("bc.type", 1), "scene.toml:9:8");
  EXPECT_EQ(d.where("bc.point", 1), "scene.toml:12:9");
  EXPECT_EQ(d.where("bc.value", 0), "default");
  EXPECT_EQ(d.where("load.magnitude", 0), "scene.toml:15:13");
  EXPECT_EQ(d.value_text("bc.point", 1), "[1.0, 2.0, 3.0]");
  EXPECT_EQ(d.value_text("bc.type", 0), "\"clamped\"");

  // issues for checks across keys: at the key, or at the element's header when defaulted
  EXPECT_EQ(d.issue("bc.type", 1, "clashes with bc[0]").to_string(),
            "scene.toml:9:8: key 'bc[1].type': clashes with bc[0]");
  EXPECT_EQ(d.issue("bc.value", 0, "too small").to_string(),
            "scene.toml:4:1: key 'bc[0].value': too small");
  EXPECT_EQ(d.issue("bc.value", 1, "x").line, 11);

  // key_paths() stays the plain keys, so logging every setting with value_text() still works
  for (const auto& k : d.key_paths()) { EXPECT_NO_THROW(d.value_text(k)) << k; }
  EXPECT_EQ(d.key_paths(), (std::vector<std::string>{"solver.dt", "model.name"}));
  EXPECT_EQ(d.array_paths(), (std::vector<std::string>{"bc", "load", "model.layers"}));
  EXPECT_EQ(d.element_key_paths("load"), (std::vector<std::string>{"load.magnitude"}));
  EXPECT_EQ(d.element_key_paths("bc").size(), 7u);
}

TEST(SchemaArrays, ArrayInsideATableAndMaxCountReached) {
  const Document d = validate(array_schema(),
                              std::string(kValidArrays) +
                                  "[[load]]\nmagnitude = 2\n"  // 16, 17
                                  "[model]\n"                  // 18
                                  "[[model.layers]]\n"         // 19
                                  "[[model.layers]]\n"         // 20
                                  "thickness = 0.5\n",         // 21
                              "scene.toml");
  EXPECT_EQ(d.count("load"), 2u);
  EXPECT_DOUBLE_EQ(d.number("load.magnitude", 1), 2.0);
  EXPECT_TRUE(d.table_present("model"));
  ASSERT_EQ(d.count("model.layers"), 2u);
  EXPECT_DOUBLE_EQ(d.number("model.layers.thickness", 0), 0.001);
  EXPECT_DOUBLE_EQ(d.number("model.layers.thickness", 1), 0.5);
  EXPECT_EQ(d.issue("model.layers.thickness", 0, "x").line, 19);
  EXPECT_EQ(d.where("model.layers.thickness", 1), "scene.toml:21:13");
}

TEST(SchemaArrays, InlineArrayOfInlineTables) {
  const char* text =
      "solver.dt = 0.1\n"                                        // 1
      "load = [{ magnitude = 1.5 }]\n"                           // 2
      "bc = [\n"                                                 // 3
      "  { type = \"fix\", nodes = \"a\" },\n"                   // 4
      "  { type = \"symmetry\", nodes = \"b\", value = 1 },\n"   // 5
      "]\n";
  const Document d = validate(array_schema(), text, "scene.toml");
  ASSERT_EQ(d.count("bc"), 2u);
  EXPECT_EQ(d.string("bc.type", 0), "fix");
  EXPECT_EQ(d.string("bc.type", 1), "symmetry");
  EXPECT_DOUBLE_EQ(d.number("bc.value", 1), 1.0);
  EXPECT_EQ(d.where("bc.type", 1), "scene.toml:5:12");
  EXPECT_EQ(d.issue("bc.value", 0, "x").to_string(), "scene.toml:4:3: key 'bc[0].value': x");
  EXPECT_DOUBLE_EQ(d.number("load.magnitude", 0), 1.5);
  // an empty array is zero elements
  EXPECT_EQ(validate(array_schema(), std::string(text) + "model.layers = []\n", "scene.toml").count("model.layers"), 0u);
}

TEST(SchemaArrays, LookupMistakesAreLogicErrors) {
  const Document d = validate(array_schema(), kValidArrays, "scene.toml");
  EXPECT_THROW(d.number("bc.value"), std::logic_error);      // array key without index
  EXPECT_THROW(d.string("bc.type"), std::logic_error);
  EXPECT_THROW(d.present("bc.type"), std::logic_error);
  EXPECT_THROW(d.where("bc.type"), std::logic_error);
  EXPECT_THROW(d.value_text("bc.type"), std::logic_error);
  EXPECT_THROW(d.issue("bc.type", "x"), std::logic_error);
  EXPECT_THROW(d.number("bc.value", 2), std::logic_error);   // past the end
  EXPECT_THROW(d.where("bc.value", 2), std::logic_error);
  EXPECT_THROW(d.issue("bc.value", 2, "x"), std::logic_error);
  EXPECT_THROW(d.number("model.layers.thickness", 0), std::logic_error);  // no elements
  EXPECT_THROW(d.number("solver.dt", 0), std::logic_error);  // index on a plain key
  EXPECT_THROW(d.integer("bc.value", 0), std::logic_error);  // wrong accessor
  EXPECT_THROW(d.number("bc.nope", 0), std::logic_error);
  EXPECT_THROW(d.count("solver"), std::logic_error);
  EXPECT_THROW(d.count("bc.type"), std::logic_error);
  EXPECT_THROW(d.table_present("bc"), std::logic_error);
  try {
    d.number("bc.value");
    FAIL();
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("[[bc]]"), std::string::npos) << e.what();
  }
}

const BadCase kBadArrayCases[] = {
    {"bad_choice_in_element_2",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"b\"\n"
     "[[bc]]\ntype = \"clamp\"\nnodes = \"c\"\n",
     12, "bc[2].type", "expected one of clamped, hinged, symmetry, fix, got 'clamp' (did you mean 'clamped'?)"},
    {"unknown_key_in_element_2",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"b\"\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"c\"\nvaleu = 2\n",
     14, "bc[2].valeu", "unknown key 'bc[2].valeu' (did you mean 'bc[2].value'?)"},
    {"unknown_key_lists_element_keys",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\nxyz = 1\n", 8,
     "bc[0].xyz", "unknown key 'bc[0].xyz'; keys in [[bc]] are: type, nodes, value, order, active, point, dofs"},
    {"wrong_type_in_element",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n"
     "[[bc]]\ntype = \"fix\"\nnodes = \"b\"\nvalue = \"big\"\n",
     11, "bc[1].value", "expected a number >= 0, got a string (\"big\")"},
    {"float_for_integer_in_element",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\norder = 2.0\n", 8,
     "bc[0].order", "expected an integer in [1, 3], got a floating-point number (2.0) (write it without a decimal point)"},
    {"list_in_element",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\ndofs = [\"x\", \"rq\"]\n", 8,
     "bc[0].dofs", "element [1]: expected one of x, y, z, rx, ry, rz, got 'rq'"},
    {"missing_required_key_in_one_element",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n\n[[bc]]\ntype = \"fix\"\n",
     9, "bc[1].nodes", "missing required key 'bc[1].nodes' (meaning: node set)"},
    {"count_below_min", "[solver]\ndt = 0.1\n", 0, "load", "expected at least 1 [[load]] table, got 0"},
    {"count_above_max",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[load]]\nmagnitude = 2\n[[load]]\nmagnitude = 3\n", 7,
     "load", "expected at most 2 [[load]] tables, got 3"},
    {"count_above_max_in_table",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[model]\n"
     "[[model.layers]]\n[[model.layers]]\n[[model.layers]]\n[[model.layers]]\n",
     9, "model.layers", "expected at most 3 [[model.layers]] tables, got 4"},
    {"plain_table_for_array",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[bc]\ntype = \"fix\"\nnodes = \"a\"\n", 5, "bc",
     "expected an array of tables [[bc]] (boundary conditions), got a single table [bc]; write each element "
     "under its own [[bc]] header"},
    {"inline_table_for_array",
     "solver.dt = 0.1\nload = { magnitude = 1 }\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n", 2, "load",
     "expected an array of tables [[load]] (applied loads), got a single table [load]"},
    {"scalar_for_array", "bc = 3\n[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n", 1, "bc",
     "expected an array of tables [[bc]] (boundary conditions), got an integer (3)"},
    {"array_for_plain_table", "[[solver]]\ndt = 0.1\n[[load]]\nmagnitude = 1\n", 1, "solver",
     "expected a table [solver] (time integration), got an array of tables [[solver]]; [solver] is a single "
     "table: write its header once, as [solver]"},
    {"scalar_element", "bc = [{ type = \"fix\", nodes = \"a\" }, 2]\n[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n",
     1, "bc[1]", "expected each element of [[bc]] to be a table { ... }, got an integer (2)"},
    {"nested_table_in_element",
     "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n[bc.extra]\nx = 1\n", 8,
     "bc[0].extra", "nested table 'bc[0].extra' is not allowed: [[bc]] elements hold plain keys only"},
    {"inline_nested_table_in_element",
     "bc = [{ type = \"fix\", nodes = \"a\", at = { x = 1 } }]\n[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n",
     1, "bc[0].at", "nested table 'bc[0].at' is not allowed"},
    {"bad_value_in_inline_element",
     "load = [{ magnitude = 1 },\n  { magnitude = -1 }]\n[solver]\ndt = 0.1\n", 2, "load[1].magnitude",
     "expected a number > 0, got -1"},
    {"unknown_array_typo", "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n[[bcs]]\ntype = \"fix\"\n", 5, "bcs",
     "unknown key 'bcs' (did you mean 'bc'?)"},
    {"element_key_outside_its_array", "nodes = \"a\"\n[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n", 1,
     "nodes", "unknown key 'nodes' (did you mean 'nodes' in a [[bc]] table?)"},
};

class BadArrayInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadArrayInput, ReportsLineKeyAndMessage) {
  const BadCase& c = GetParam();
  const auto issues = array_issues(c.text);
  EXPECT_TRUE(has_issue(issues, "scene.toml", c.line, c.key, c.fragment))
      << "wanted scene.toml:" << c.line << " key '" << c.key << "' containing \"" << c.fragment
      << "\"\ngot:\n"
      << dump(issues);
  EXPECT_EQ(issues.size(), 1u) << dump(issues);
}

INSTANTIATE_TEST_SUITE_P(Schema, BadArrayInput, ::testing::ValuesIn(kBadArrayCases),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(SchemaArrays, MessagesAsAWhole) {
  try {
    validate(array_schema(),
             "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n"
             "[[bc]]\ntype = \"fix\"\nnodes = \"a\"\n[[bc]]\nnodes = \"b\"\n[[bc]]\ntype = \"clamp\"\nnodes = \"c\"\n",
             "scene.toml");
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()),
              "scene.toml:8:1: key 'bc[1].type': missing required key 'bc[1].type' (meaning: kind of support)\n"
              "scene.toml:11:8: key 'bc[2].type': expected one of clamped, hinged, symmetry, fix, got 'clamp' "
              "(did you mean 'clamped'?)");
  }
  try {
    validate(array_schema(), "[solver]\ndt = 0.1\n", "scene.toml");
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "scene.toml: key 'load': expected at least 1 [[load]] table, got 0");
  }
  // exact counts, and a count below the minimum with elements given points at the first one
  Schema s;
  s.table_array("pair", "two of them", 2, 2).number("pair.x", "x", 0.0);
  try {
    validate(s, "\n[[pair]]\n", "scene.toml");
    FAIL() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "scene.toml:2:1: key 'pair': expected exactly 2 [[pair]] tables, got 1");
  }
  // an absent optional parent table: its arrays are not counted
  Schema t;
  t.table("opt", "optional").table_array("opt.items", "items", 1).number("opt.items.x", "x", 0.0);
  EXPECT_EQ(validate(t, "", "scene.toml").count("opt.items"), 0u);
  EXPECT_THROW(validate(t, "[opt]\n", "scene.toml"), SceneError);
}

TEST(SchemaArrays, ErrorsInOneElementDoNotLeakIntoOthers) {
  const auto issues = array_issues(
      "[solver]\ndt = 0.1\n[[load]]\nmagnitude = 1\n"
      "[[bc]]\ntype = \"fix\"\nnodes = 3\n"  // 5-7: wrong type, not also "missing"
      "[[bc]]\ntype = \"fix\"\n");          // 8-9: missing nodes
  ASSERT_EQ(issues.size(), 2u) << dump(issues);
  EXPECT_EQ(issues[0].key, "bc[0].nodes");
  EXPECT_EQ(issues[0].line, 7);
  EXPECT_NE(issues[0].message.find("expected a string"), std::string::npos);
  EXPECT_EQ(issues[1].key, "bc[1].nodes");
  EXPECT_EQ(issues[1].line, 8);
}

TEST(SchemaArrays, OverridesIntoAnElement) {
  const Document d = validate(array_schema(), kValidArrays, "scene.toml",
                              {"bc[1].value=3", "bc[0].type=fix", "bc[0].point=[4, 5, 6]", "load[0].magnitude=7"});
  EXPECT_DOUBLE_EQ(d.number("bc.value", 1), 3.0);
  EXPECT_EQ(d.where("bc.value", 1), "--set bc[1].value=3");
  EXPECT_TRUE(d.present("bc.value", 1));
  EXPECT_DOUBLE_EQ(d.number("bc.value", 0), 0.0);  // the other element keeps its default
  EXPECT_FALSE(d.present("bc.value", 0));
  EXPECT_EQ(d.string("bc.type", 0), "fix");
  EXPECT_EQ(d.string("bc.type", 1), "hinged");
  EXPECT_EQ(d.numbers("bc.point", 0), (std::vector<double>{4, 5, 6}));
  EXPECT_DOUBLE_EQ(d.number("load.magnitude", 0), 7.0);
  EXPECT_EQ(d.issue("bc.value", 1, "x").to_string(), "--set bc[1].value=3: key 'bc[1].value': x");
  EXPECT_EQ(d.count("bc"), 2u);
  // an override supplies a required key the element lacks
  const Document fixed = validate(array_schema(), std::string(kValidArrays) + "[[bc]]\ntype = \"fix\"\n",
                                  "scene.toml", {"bc[2].nodes=n"});
  EXPECT_EQ(fixed.string("bc.nodes", 2), "n");
  EXPECT_EQ(fixed.where("bc.nodes", 2), "--set bc[2].nodes=n");
  EXPECT_EQ(fixed.issue("bc.value", 2, "x").line, 16);
}

const OverrideCase kBadArrayOverrides[] = {
    {"index_past_end", "bc[2].value=3", "bc[2].value",
     "index 2 is past the end: scene.toml has 2 [[bc]] tables, bc[0] to bc[1]; --set can only change a key of "
     "an element the file has"},
    {"index_into_one_element", "load[1].magnitude=3", "load[1].magnitude",
     "index 1 is past the end: scene.toml has 1 [[load]] table, load[0];"},
    {"index_into_absent_array", "model.layers[0].thickness=1", "model.layers[0].thickness",
     "index 0 is past the end: scene.toml has no [[model.layers]] table"},
    {"huge_index", "bc[123456789012345678901234567890].value=1", "bc[123456789012345678901234567890].value",
     "index 123456789012345678901234567890 is past the end"},
    {"unknown_key_in_element", "bc[1].valeu=3", "bc[1].valeu", "unknown key 'bc[1].valeu' (did you mean 'bc[1].value'?)"},
    {"unknown_key_lists_keys", "bc[0].xyz=3", "bc[0].xyz", "keys in [[bc]] are: type, nodes"},
    {"deeper_path_in_element", "bc[0].value.x=3", "bc[0].value.x", "'bc[0].value' is a number, it has no key 'x'"},
    {"bad_value_in_element", "bc[1].value=-1", "bc[1].value", "expected a number >= 0, got -1"},
    {"bad_choice_in_element", "bc[0].type=clamp", "bc[0].type",
     "expected one of clamped, hinged, symmetry, fix, got 'clamp' (did you mean 'clamped'?)"},
    {"empty_value_in_element", "bc[0].value=", "bc[0].value", "no value after '=': write --set bc[0].value=VALUE"},
    {"no_index", "bc.value=3", "bc.value",
     "'bc.value' is a key of the array of tables [[bc]]; name the element: --set bc[INDEX].value=VALUE"},
    {"no_index_unknown_key", "bc.valeu=3", "bc.valeu", "name the element: --set bc[INDEX].valeu=VALUE"},
    {"whole_array", "bc=[]", "bc", "'bc' is an array of tables [[bc]]; --set cannot replace a whole array"},
    {"whole_element", "bc[0]={}", "bc[0]", "--set cannot replace a whole element bc[0]"},
    {"bad_index", "bc[x].value=1", "bc[x].value", "expected --set bc[INDEX].KEY=VALUE"},
    {"negative_index", "bc[-1].value=1", "bc[-1].value", "expected --set bc[INDEX].KEY=VALUE"},
    {"unclosed_index", "bc[0.value=1", "bc[0.value", "expected --set bc[INDEX].KEY=VALUE"},
    {"index_on_plain_table", "solver[0].dt=1", "solver[0].dt",
     "'solver' is a table, not an array of tables: write --set solver.KEY=VALUE, without an index"},
    {"unknown_array", "bcc[0].type=fix", "bcc[0].type", "unknown key 'bcc' (did you mean 'bc'?)"},
};

class BadArrayOverride : public ::testing::TestWithParam<OverrideCase> {};

TEST_P(BadArrayOverride, NamesTheSetArgument) {
  const OverrideCase& c = GetParam();
  const auto issues = array_issues(kValidArrays, {c.arg});
  EXPECT_TRUE(has_issue(issues, std::string("--set ") + c.arg, 0, c.key, c.fragment))
      << "wanted '--set " << c.arg << "' key '" << c.key << "' containing \"" << c.fragment
      << "\"\ngot:\n"
      << dump(issues);
  EXPECT_EQ(issues.size(), 1u) << dump(issues);
}

INSTANTIATE_TEST_SUITE_P(Schema, BadArrayOverride, ::testing::ValuesIn(kBadArrayOverrides),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(SchemaArrays, ElementOverrideAfterSyntaxErrorChecksOnlyTheValue) {
  // the file's elements are unknown: no "past the end", but the value itself is still checked
  auto issues = array_issues("[[bc]\n", {"bc[5].value=1"});
  ASSERT_EQ(issues.size(), 1u) << dump(issues);
  EXPECT_NE(issues[0].message.find("TOML syntax error"), std::string::npos);
  issues = array_issues("[[bc]\n", {"bc[5].value=-1"});
  ASSERT_EQ(issues.size(), 2u) << dump(issues);
  EXPECT_EQ(issues[1].key, "bc[5].value");
}

TEST(SchemaArrays, MarkdownReferenceHasASectionPerArray) {
  const std::string md = array_schema().markdown_reference();
  const auto bc = md.find("### [[bc]] (array of tables, 0 or more)\n");
  const auto load = md.find("### [[load]] (array of tables, 1 to 2)\n");
  const auto layers = md.find("### [[model.layers]] (array of tables, 0 to 3)\n");
  ASSERT_NE(bc, std::string::npos) << md;
  ASSERT_NE(load, std::string::npos) << md;
  ASSERT_NE(layers, std::string::npos) << md;
  EXPECT_LT(md.find("### `[solver]`"), bc);
  EXPECT_LT(bc, load);
  EXPECT_LT(load, md.find("### `[model]`"));
  EXPECT_LT(md.find("### `[model]`"), layers);
  const auto type_row = md.find("| `bc.type` | choice | **required** | `clamped`, `hinged`, `symmetry`, `fix` | kind of support |");
  EXPECT_NE(type_row, std::string::npos) << md;
  EXPECT_GT(type_row, bc);
  EXPECT_LT(type_row, load);  // inside the [[bc]] section
  EXPECT_NE(md.find("| `bc.point` | list of numbers [m] | `[0.0, 0.0, 0.0]` | length 3 | reference point |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("boundary conditions (write one `[[bc]]` table per element)"), std::string::npos) << md;
  const auto mag = md.find("| `load.magnitude` |");
  EXPECT_GT(mag, load);
  EXPECT_LT(mag, md.find("### `[model]`"));
  // arrays are not listed as plain tables
  EXPECT_EQ(md.find("### `[bc]`"), std::string::npos);
  Schema exact;
  exact.table_array("pair", "two", 2, 2).number("pair.x", "x", 0.0);
  EXPECT_NE(exact.markdown_reference().find("### [[pair]] (array of tables, exactly 2)"), std::string::npos);
}

TEST(SchemaArrays, BadDeclarationsAreLogicErrors) {
  Schema s;
  s.table_array("bc", "supports");
  EXPECT_THROW(s.table_array("bc", "twice"), std::logic_error);
  EXPECT_THROW(s.table("bc", "array and table"), std::logic_error);
  EXPECT_THROW(s.table("bc.sub", "table in an array"), std::logic_error);
  EXPECT_THROW(s.table_array("bc.sub", "array in an array"), std::logic_error);
  EXPECT_THROW(s.table_array("nope.items", "undeclared parent"), std::logic_error);
  EXPECT_THROW(s.table_array("few", "min > max", 3, 2), std::logic_error);
  EXPECT_THROW(s.table_array("none", "max 0", 0, 0), std::logic_error);
  EXPECT_THROW(s.table_array("undocumented", ""), std::logic_error);
  EXPECT_THROW(s.number("bc.x", "default out of range", -1.0, Range::positive()), std::logic_error);
  s.number("bc.x", "fine", 1.0);
  EXPECT_EQ(s.array_of("bc.x"), "bc");
  EXPECT_EQ(s.find_array("bc")->min_count, 0u);
  EXPECT_EQ(s.find_array("bc.x"), nullptr);
  s.table("plain", "a table");
  EXPECT_EQ(s.find_array("plain"), nullptr);
  s.number("plain.y", "fine", 1.0);
  EXPECT_EQ(s.array_of("plain.y"), "");
}

// Live edits (the GUI's `set` while a run goes on) are read and checked like --set values, but
// only for keys declared live; the issue names the key and the "live key=value" it came from.
Schema live_schema() {
  Schema s = test_schema();
  s.live("solver.rho_inf").live("model.beam.gravity").live("solver.max_iter");
  return s;
}

std::string live_error(const Schema& s, const std::string& key, const std::string& value) {
  try {
    validate_live(s, key, value);
  } catch (const SceneError& e) {
    EXPECT_EQ(e.issues.size(), 1u) << e.what();
    if (!e.issues.empty()) {
      EXPECT_EQ(e.issues[0].key, key) << e.what();
    }
    return e.what();
  }
  return "";
}

TEST(SchemaLive, ValuesComeBackTyped) {
  const Schema s = live_schema();
  EXPECT_EQ(s.live_keys(), (std::vector<std::string>{"solver.rho_inf", "solver.max_iter", "model.beam.gravity"}));
  EXPECT_EQ(std::get<double>(validate_live(s, "solver.rho_inf", "0.5")), 0.5);
  EXPECT_EQ(std::get<double>(validate_live(s, "solver.rho_inf", " 1 ")), 1.0);  // an integer is a number
  EXPECT_EQ(std::get<long long>(validate_live(s, "solver.max_iter", "7")), 7);
  EXPECT_EQ(std::get<std::vector<double>>(validate_live(s, "model.beam.gravity", "[0, 0, 9.81]")),
            (std::vector<double>{0, 0, 9.81}));
}

TEST(SchemaLive, BadValuesAreRefusedLikeAnOverride) {
  const Schema s = live_schema();
  EXPECT_EQ(live_error(s, "solver.rho_inf", "1.5"),
            "live solver.rho_inf=1.5: key 'solver.rho_inf': expected a number in [0, 1], got 1.5");
  std::string e = live_error(s, "solver.rho_inf", "x");
  EXPECT_NE(e.find("expected a number in [0, 1], got a string (\"x\")"), std::string::npos) << e;
  e = live_error(s, "solver.max_iter", "2.0");
  EXPECT_NE(e.find("expected an integer >= 1"), std::string::npos) << e;
  e = live_error(s, "model.beam.gravity", "[1, 2]");
  EXPECT_NE(e.find("expected a list of numbers (length 3), got 2 elements"), std::string::npos) << e;
  e = live_error(s, "model.beam.gravity", "[0, 0, nan]");
  EXPECT_NE(e.find("expected a finite number"), std::string::npos) << e;
  e = live_error(s, "solver.rho_inf", "");
  EXPECT_NE(e.find("no value"), std::string::npos) << e;
}

TEST(SchemaLive, KeysNotDeclaredLiveAreRefusedWithTheLiveKeys) {
  const Schema s = live_schema();
  const std::string live = "(live keys: solver.rho_inf, solver.max_iter, model.beam.gravity)";
  EXPECT_EQ(live_error(s, "solver.dt", "0.1"),
            "live solver.dt=0.1: key 'solver.dt': 'solver.dt' cannot change while the model runs " + live);
  std::string e = live_error(s, "solver.nope", "1");
  EXPECT_NE(e.find(live), std::string::npos) << e;
  e = live_error(test_schema(), "solver.dt", "0.1");
  EXPECT_NE(e.find("this model has no live keys"), std::string::npos) << e;
}

TEST(SchemaLive, DeclarationMistakesAreLogicErrorsAndTheReferenceSaysLive) {
  Schema s = live_schema();
  EXPECT_THROW(s.live("solver.undeclared"), std::logic_error);
  s.table_array("bc", "supports").number("bc.x", "fine", 1.0);
  EXPECT_THROW(s.live("bc.x"), std::logic_error);
  const std::string md = s.markdown_reference();
  EXPECT_NE(md.find("| spectral radius at infinity (live: changes while the run goes on) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| time step |"), std::string::npos) << md;  // not live: as before
}

TEST(SchemaArrays, SuggestionForAWordCutShort) {
  EXPECT_EQ(text::closest("clamp", {"clamped", "hinged", "symmetry", "fix"}), "clamped");
  EXPECT_EQ(text::closest("sym", {"clamped", "hinged", "symmetry", "fix"}), "");  // too short a part
  EXPECT_EQ(text::closest("ab", {"abc"}), "abc");  // one edit: the usual rule
  EXPECT_EQ(text::closest("hin", {"hinged"}), "hinged");
}

}  // namespace
}  // namespace ff::scene
