#pragma once
/// \file schema_text.h
/// Small text helpers shared by the schema sources (internal to core/scene): number formatting,
/// quoting, "did you mean" suggestions. No toml++ here.

#include <string>
#include <string_view>
#include <vector>

#include "core/scene/schema_value.h"

namespace ff::scene::text {

/// Shortest text that reads back to the same double: 0.01, 2, 1e-06, -0.5.
std::string number(double x);
/// As number(), but integral values keep a ".0" so they read as floating point (TOML style).
std::string toml_number(double x);
/// `s` in double quotes with ", \ and control characters escaped (TOML basic string).
std::string quoted(std::string_view s);
/// `s` cut to at most `max` characters, with "..." when cut.
std::string clip(std::string_view s, std::size_t max = 60);
/// Items joined by `sep`.
std::string join(const std::vector<std::string>& items, std::string_view sep);
/// `s` cut at every `sep`, each piece trimmed of blanks and tabs ("a, b" -> {"a", "b"}).
std::vector<std::string> split_trimmed(const std::string& s, char sep);
/// The whole of `s` as a finite number, or false.
bool parse_finite(const std::string& s, double* v);
/// Value as TOML text ("" for monostate).
std::string toml_value(const Value& v);

/// Optimal-string-alignment distance (insertions, deletions, substitutions, adjacent
/// transpositions), case-insensitive.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// The candidate closest to `word` if it is close enough to be a plausible typo; failing that,
/// the shortest candidate that `word` begins (a word cut short: 'clamp' for 'clamped'; `word` at
/// least 3 letters and at least half the candidate); else "".
std::string closest(std::string_view word, const std::vector<std::string>& candidates);

/// "a number", "an integer", "a boolean (true or false)", "a string", ...
std::string kind_noun(Kind kind);

}  // namespace ff::scene::text
