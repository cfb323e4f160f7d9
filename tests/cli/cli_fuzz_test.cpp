// Seeded, bounded fuzzing of what users hand flexframe (issue 12): mutants of the bundled scenes
// and of quad meshes (OBJ, ASCII PLY, binary PLY) go through `flexframe check`, a few through a
// shortened `flexframe run`. Every mutant must end honestly:
//   - exit 0 (check: valid; run: completed), or run's 3 (diverged) / 4 (incomplete), or
//   - exit 2 naming where: `<scene>:<line>:` (or the `--set` argument) and a key ('key ...')
//     or a TOML syntax error; an absent table is named by file and key alone (it has no line),
// never a signal, another exit code or a hang past the per-mutant timeout.
// The corpus tests/cli/fuzz_corpus/ (past crashers) runs first, every time. A failing mutant is
// reported with the seed, its number, the mutation and its file (kept under
// FF_BINARY_DIR/test_out/cli/CliFuzz.<test>/); copy it into the corpus once fixed.
// FF_FUZZ_SEED=<n> and FF_FUZZ_SCALE=<k> (k times the mutants) explore beyond the fixed seed.

#include <gtest/gtest.h>

#include <bit>
#include <cinttypes>
#include <cstdio>
#include <functional>
#include <random>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

constexpr std::uint64_t kSeed = 12;  // issue 12; a fixed seed: the same mutants on every run
constexpr int kSceneMutants = 120;   // ~0.1 s each through `check` (Release)
constexpr int kMeshMutants = 30;     // per mesh kind (OBJ, ASCII PLY, binary PLY, MSH 4 and 2.2, STEP, INP)
constexpr int kRunMutants = 6;       // valid scene mutants also run, ~1 s each

// sanitizer builds run every child several times slower
#if defined(__SANITIZE_ADDRESS__)
#define FF_FUZZ_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define FF_FUZZ_SANITIZED 1
#endif
#endif
#ifdef FF_FUZZ_SANITIZED
constexpr double kSlow = 8.0;
#else
constexpr double kSlow = 1.0;
#endif
const double kCheckTimeout = 15.0 * kSlow;
const double kRunTimeout = 30.0 * kSlow;

std::uint64_t fuzz_seed() {
  const char* s = std::getenv("FF_FUZZ_SEED");
  return s && *s ? std::strtoull(s, nullptr, 0) : kSeed;
}

int fuzz_scale() {
  const char* s = std::getenv("FF_FUZZ_SCALE");
  return s && *s ? std::max(1, std::atoi(s)) : 1;
}

/// mt19937_64 is specified exactly by the standard (unlike the distributions), so a seed names
/// the same mutants everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : g_(seed) {}
  std::size_t below(std::size_t n) { return n ? static_cast<std::size_t>(g_() % n) : 0; }
  template <class T>
  const T& pick(const std::vector<T>& v) { return v[below(v.size())]; }

 private:
  std::mt19937_64 g_;
};

/// Each mutant has its own generator, so one can be reproduced without the ones before it.
Rng mutant_rng(std::uint64_t seed, int stream, int index) {
  return Rng(seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(stream) * 1000003ULL +
             static_cast<std::uint64_t>(index));
}

// ---- text helpers --------------------------------------------------------------------------------

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t nl = text.find('\n', start);
    if (nl == std::string::npos) {
      lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, nl - start));
    start = nl + 1;
  }
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  return text;
}

std::string trim_left(const std::string& s) {
  const std::size_t i = s.find_first_not_of(" \t");
  return i == std::string::npos ? "" : s.substr(i);
}

bool starts_with(const std::string& s, const std::string& p) { return s.compare(0, p.size(), p) == 0; }

/// Where the value of a `key = value` line is ([begin, end), comment excluded); nullopt for
/// headers, comments and blank lines.
std::optional<std::pair<std::size_t, std::size_t>> value_span(const std::string& line) {
  const std::string t = trim_left(line);
  if (t.empty() || t[0] == '#' || t[0] == '[') return std::nullopt;
  const std::size_t eq = line.find('=');
  if (eq == std::string::npos) return std::nullopt;
  std::size_t b = line.find_first_not_of(" \t", eq + 1);
  if (b == std::string::npos) return std::nullopt;
  std::size_t e = b;
  char quote = 0;
  for (; e < line.size(); ++e) {
    const char c = line[e];
    if (quote) {
      if (c == '\\' && quote == '"') ++e;
      else if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#') {
      break;
    }
  }
  while (e > b && (line[e - 1] == ' ' || line[e - 1] == '\t')) --e;
  return std::pair{b, e};
}

/// Numeric tokens of a value, outside strings ([begin, end) in the line).
std::vector<std::pair<std::size_t, std::size_t>> number_spans(const std::string& line, std::size_t b, std::size_t e) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  char quote = 0;
  for (std::size_t i = b; i < e; ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '"' || c == '\'') {
      quote = c;
      continue;
    }
    const bool digit = std::isdigit(static_cast<unsigned char>(c));
    const bool signed_digit = (c == '-' || c == '+') && i + 1 < e && std::isdigit(static_cast<unsigned char>(line[i + 1]));
    if (!digit && !signed_digit) continue;
    std::size_t j = i + 1;
    while (j < e && (std::isalnum(static_cast<unsigned char>(line[j])) || std::strchr("._+-", line[j]))) ++j;
    out.emplace_back(i, j);
    i = j - 1;
  }
  return out;
}

std::string quoted_line(int n, const std::string& line) {
  std::string shown = line.size() > 60 ? line.substr(0, 60) + "..." : line;
  return "line " + std::to_string(n) + " '" + shown + "'";
}

// ---- mutations -----------------------------------------------------------------------------------

struct Mutant {
  std::string what;  ///< the mutation, for a person
  std::string text;  ///< the mutated file
};

using Mutation = std::function<std::optional<Mutant>(const std::string& text, Rng& rng)>;

/// Indices of the lines satisfying `pred`.
std::vector<std::size_t> lines_where(const std::vector<std::string>& lines,
                                     const std::function<bool(const std::string&)>& pred) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (pred(lines[i])) out.push_back(i);
  return out;
}

std::optional<Mutant> truncate(const std::string& text, Rng& rng) {
  if (text.empty()) return std::nullopt;
  const std::size_t at = rng.below(text.size());
  return Mutant{"truncated to " + std::to_string(at) + " of " + std::to_string(text.size()) + " bytes", text.substr(0, at)};
}

std::optional<Mutant> delete_line(const std::string& text, Rng& rng) {
  std::vector<std::string> lines = split_lines(text);
  const auto idx = lines_where(lines, [](const std::string& l) { return !trim_left(l).empty(); });
  if (idx.empty()) return std::nullopt;
  const std::size_t i = rng.pick(idx);
  const std::string what = "deleted " + quoted_line(static_cast<int>(i) + 1, lines[i]);
  lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(i));
  return Mutant{what, join_lines(lines)};
}

std::optional<Mutant> duplicate_line(const std::string& text, Rng& rng) {
  std::vector<std::string> lines = split_lines(text);
  const auto idx = lines_where(lines, [](const std::string& l) { return !trim_left(l).empty(); });
  if (idx.empty()) return std::nullopt;
  const std::size_t i = rng.pick(idx);
  const std::string what = "duplicated " + quoted_line(static_cast<int>(i) + 1, lines[i]);
  lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(i), lines[i]);
  return Mutant{what, join_lines(lines)};
}

// scenes ------------------------------------------------------------------------------------------

bool is_header(const std::string& l) { return starts_with(trim_left(l), "["); }
bool is_key_line(const std::string& l) { return value_span(l).has_value(); }

std::optional<Mutant> duplicate_table(const std::string& text, Rng& rng) {
  std::vector<std::string> lines = split_lines(text);
  const auto headers = lines_where(lines, is_header);
  if (headers.empty()) return std::nullopt;
  const std::size_t h = rng.pick(headers);
  std::size_t end = h + 1;
  while (end < lines.size() && !is_header(lines[end])) ++end;
  const std::vector<std::string> block(lines.begin() + static_cast<std::ptrdiff_t>(h),
                                       lines.begin() + static_cast<std::ptrdiff_t>(end));
  lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(end), block.begin(), block.end());
  return Mutant{"duplicated the table at " + quoted_line(static_cast<int>(h) + 1, lines[h]) + " (" +
                    std::to_string(block.size()) + " lines)",
                join_lines(lines)};
}

std::optional<Mutant> swap_values(const std::string& text, Rng& rng) {
  std::vector<std::string> lines = split_lines(text);
  const auto keys = lines_where(lines, is_key_line);
  if (keys.size() < 2) return std::nullopt;
  const std::size_t a = rng.pick(keys);
  std::size_t b = rng.pick(keys);
  if (a == b) b = keys[(std::find(keys.begin(), keys.end(), a) - keys.begin() + 1) % keys.size()];
  const auto [ab, ae] = *value_span(lines[a]);
  const auto [bb, be] = *value_span(lines[b]);
  const std::string va = lines[a].substr(ab, ae - ab), vb = lines[b].substr(bb, be - bb);
  lines[a].replace(ab, ae - ab, vb);
  lines[b].replace(bb, be - bb, va);
  return Mutant{"swapped the values of lines " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " ('" + va +
                    "' <-> '" + vb + "')",
                join_lines(lines)};
}

std::optional<Mutant> extreme_number(const std::string& text, Rng& rng) {
  // 1e-12 and 1e200 (issue 30): a dimension that shapes degenerate elements or overflows squares
  static const std::vector<std::string> values = {"0",    "-1",  "1e308", "-1e308", "nan", "inf",
                                                  "-inf", "1",   "0.0",   "-0.0",   "5e-324",
                                                  "9223372036854775807", "-9223372036854775808", "2147483648",
                                                  "1e-12", "1e200"};
  std::vector<std::string> lines = split_lines(text);
  const auto idx = lines_where(lines, [](const std::string& l) {
    const auto v = value_span(l);
    return v && !number_spans(l, v->first, v->second).empty();
  });
  if (idx.empty()) return std::nullopt;
  const std::size_t i = rng.pick(idx);
  const auto v = *value_span(lines[i]);
  const auto [nb, ne] = rng.pick(number_spans(lines[i], v.first, v.second));
  const std::string& to = rng.pick(values);
  const std::string what = "line " + std::to_string(i + 1) + ": '" + lines[i].substr(nb, ne - nb) + "' -> '" + to + "'";
  lines[i].replace(nb, ne - nb, to);
  return Mutant{what, join_lines(lines)};
}

std::optional<Mutant> wrong_type(const std::string& text, Rng& rng) {
  static const std::vector<std::string> values = {
      "\"text\"", "true", "[1, 2, 3]", "{ a = 1 }", "1979-05-27T07:32:00Z", "[]", "\"\"", "[[1], [\"a\"]]",
      "0x7fffffff", "07:32:00", "\"1.0\"", "[\"inertia\", 3]", "{}", "'''\nmulti\n'''"};
  std::vector<std::string> lines = split_lines(text);
  const auto keys = lines_where(lines, is_key_line);
  if (keys.empty()) return std::nullopt;
  const std::size_t i = rng.pick(keys);
  const auto [b, e] = *value_span(lines[i]);
  const std::string& to = rng.pick(values);
  const std::string what = "line " + std::to_string(i + 1) + ": value '" + lines[i].substr(b, e - b) + "' -> " + to;
  lines[i].replace(b, e - b, to);
  return Mutant{what, join_lines(lines)};
}

std::optional<Mutant> unicode(const std::string& text, Rng& rng) {
  std::vector<std::string> lines = split_lines(text);
  const auto keys = lines_where(lines, is_key_line);
  if (keys.empty()) return std::nullopt;
  const std::size_t i = rng.pick(keys);
  const std::string before = lines[i];
  std::string what;
  switch (rng.below(7)) {
    case 0: {  // a non-ASCII bare key
      const std::size_t k = lines[i].find_first_not_of(" \t");
      lines[i].insert(k, "\xC3\xA9");
      what = "'é' before the key";
      break;
    }
    case 1: {  // the same key, quoted with a look-alike letter (Cyrillic 'а')
      const std::size_t k = lines[i].find_first_not_of(" \t"), eq = lines[i].find('=');
      lines[i] = "\"\xD0\xB0" + lines[i].substr(k, eq - k) + "\" " + lines[i].substr(eq);
      what = "key quoted with a Cyrillic letter";
      break;
    }
    case 2: {  // a string value of many scripts, a right-to-left override and an emoji
      const auto [b, e] = *value_span(lines[i]);
      lines[i].replace(b, e - b, "\"\xC3\x9C\x6E\xC3\xAF \xE2\x80\xAE \xF0\x9F\x98\x80 \xE4\xB8\xAD\"");
      what = "value -> a string of mixed scripts";
      break;
    }
    case 3: {  // invalid UTF-8 inside a value
      const auto [b, e] = *value_span(lines[i]);
      lines[i].insert(b + (e - b) / 2, "\xC3\x28\xFF");
      what = "invalid UTF-8 bytes in the value";
      break;
    }
    case 4: {  // a NUL byte
      const auto [b, e] = *value_span(lines[i]);
      lines[i].insert(b + (e - b) / 2, std::string(1, '\0'));
      what = "NUL byte in the value";
      break;
    }
    case 5:  // a byte-order mark in the middle of the file
      lines[i] = "\xEF\xBB\xBF" + lines[i];
      what = "byte-order mark before the line";
      break;
    default: {  // an escape that is not TOML
      const auto [b, e] = *value_span(lines[i]);
      lines[i].replace(b, e - b, "\"\\u00\\x41\\uD800\"");
      what = "value -> a string with invalid escapes";
      break;
    }
  }
  return Mutant{"line " + std::to_string(i + 1) + ": " + what, join_lines(lines)};
}

// issue 30: a string value that names a path outside the output folder (a scene from a stranger
// must be refused at its line, never write or delete there)
std::optional<Mutant> path_string(const std::string& text, Rng& rng) {
  static const std::vector<std::string> values = {"\"../../victim\"", "\"/tmp/victim\"", "\"a/b\"", "\"..\"",
                                                  "\"C:\\\\x\"", "\"./\"", "\"out/../..\""};
  std::vector<std::string> lines = split_lines(text);
  const auto idx = lines_where(lines, [](const std::string& l) {
    const auto v = value_span(l);
    return is_key_line(l) && v && l[v->first] == '"';
  });
  if (idx.empty()) return std::nullopt;
  const std::size_t i = rng.pick(idx);
  const auto [b, e] = *value_span(lines[i]);
  const std::string& to = rng.pick(values);
  const std::string what = "line " + std::to_string(i + 1) + ": value '" + lines[i].substr(b, e - b) + "' -> " + to;
  lines[i].replace(b, e - b, to);
  return Mutant{what, join_lines(lines)};
}

std::optional<Mutant> apply_any(const std::vector<std::pair<const char*, Mutation>>& ops, const std::string& text, Rng& rng) {
  for (int attempt = 0; attempt < 16; ++attempt) {
    const auto& [name, op] = ops[rng.below(ops.size())];
    if (auto m = op(text, rng)) {
      m->what = std::string(name) + ": " + m->what;
      return m;
    }
  }
  return std::nullopt;
}

const std::vector<std::pair<const char*, Mutation>>& scene_mutations() {
  static const std::vector<std::pair<const char*, Mutation>> ops = {
      {"delete line", delete_line},     {"duplicate line", duplicate_line}, {"duplicate table", duplicate_table},
      {"swap values", swap_values},     {"extreme number", extreme_number}, {"extreme number", extreme_number},
      {"wrong type", wrong_type},       {"unicode", unicode},               {"truncate", truncate},
      {"path string", path_string}};
  return ops;
}

// meshes ------------------------------------------------------------------------------------------

/// Replaces the `k`-th whitespace-separated token of `line` (nullopt when it has fewer).
std::optional<std::string> replace_token(const std::string& line, std::size_t k, const std::string& to) {
  std::size_t pos = 0;
  for (std::size_t n = 0;; ++n) {
    const std::size_t b = line.find_first_not_of(" \t", pos);
    if (b == std::string::npos) return std::nullopt;
    const std::size_t e = std::min(line.find_first_of(" \t", b), line.size());
    if (n == k) return line.substr(0, b) + to + line.substr(e);
    pos = e;
  }
}

std::size_t token_count(const std::string& line) {
  std::istringstream s(line);
  std::size_t n = 0;
  for (std::string t; s >> t;) ++n;
  return n;
}

/// A mutation of one line chosen by `pred`: token `first + below(tokens - first)` becomes one of `values`.
std::optional<Mutant> token_mutation(const std::string& text, Rng& rng, const std::function<bool(const std::string&)>& pred,
                                     std::size_t first, const std::vector<std::string>& values) {
  std::vector<std::string> lines = split_lines(text);
  const auto idx = lines_where(lines, [&](const std::string& l) { return pred(l) && token_count(l) > first; });
  if (idx.empty()) return std::nullopt;
  const std::size_t i = rng.pick(idx);
  const std::size_t k = first + rng.below(token_count(lines[i]) - first);
  const std::string& to = rng.pick(values);
  const std::string what = quoted_line(static_cast<int>(i) + 1, lines[i]) + ", token " + std::to_string(k) + " -> '" + to + "'";
  lines[i] = *replace_token(lines[i], k, to);
  return Mutant{what, join_lines(lines)};
}

const std::vector<std::string> kNonFinite = {"nan", "-nan", "inf", "-inf", "1e308", "1e999", "NaN", "0x1p3", "1e-320", ""};

std::vector<std::pair<const char*, Mutation>> obj_mutations() {
  const auto face = [](const std::string& l) { return starts_with(l, "f "); };
  const auto vertex = [](const std::string& l) { return starts_with(l, "v "); };
  return {
      {"truncate", truncate},
      {"delete line", delete_line},
      {"duplicate line", duplicate_line},
      {"index out of range",
       [=](const std::string& t, Rng& r) {
         return token_mutation(t, r, face, 1, {"0", "82", "-82", "2147483648", "-2147483649", "99999999999999999999", "1/",
                                                "//", "a", "1//999"});
       }},
      {"non-finite coordinate", [=](const std::string& t, Rng& r) { return token_mutation(t, r, vertex, 1, kNonFinite); }},
      // issue 30: every corner gets one normal, tilted from the plate's +z (a director off the surface)
      {"tilted normals",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         static const std::vector<double> tilts = {0.0, 3.0, 10.0, 30.0, 89.0, 90.0, 180.0};
         const double tilt = r.pick(tilts), a = tilt * std::acos(-1.0) / 180.0;
         std::ostringstream vn;
         vn.precision(17);
         vn << "vn 0 " << -std::sin(a) << " " << std::cos(a);
         std::vector<std::string> lines = split_lines(t);
         bool any = false;
         for (std::string& l : lines) {
           if (!face(l)) continue;
           std::istringstream in(l.substr(2));
           std::string out = "f";
           for (std::string v; in >> v;) out += " " + v + "//1";
           l = out;
           any = true;
         }
         if (!any) return std::nullopt;
         lines.insert(lines.begin(), vn.str());
         return Mutant{"every corner's normal tilted " + std::to_string(tilt) + " deg", join_lines(lines)};
       }},
      {"non-quad face",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         std::vector<std::string> lines = split_lines(t);
         const auto idx = lines_where(lines, face);
         if (idx.empty()) return std::nullopt;
         const std::size_t i = r.pick(idx);
         const std::string before = lines[i];
         switch (r.below(4)) {
           case 0: lines[i] = lines[i].substr(0, lines[i].find_last_of(' ')); break;  // a triangle
           case 1: lines[i] += " 1"; break;                                           // a pentagon
           case 2: lines[i] = "f"; break;                                             // no vertices
           default: lines[i] = "f 1 1 1 1"; break;                                    // a degenerate quad
         }
         return Mutant{quoted_line(static_cast<int>(i) + 1, before) + " -> '" + lines[i] + "'", join_lines(lines)};
       }},
  };
}

/// Text meshes (.msh and STEP through Gmsh, Abaqus .inp): cut, lines lost or repeated, and
/// numbers on the data lines replaced by non-finite, huge, negative or non-numbers.
std::vector<std::pair<const char*, Mutation>> text_mesh_mutations() {
  const auto numbers = [](const std::string& l) {
    return !l.empty() && (std::isdigit(static_cast<unsigned char>(l[0])) || l[0] == '#' || l[0] == '-');
  };
  return {
      {"truncate", truncate},
      {"delete line", delete_line},
      {"duplicate line", duplicate_line},
      {"bad number",
       [=](const std::string& t, Rng& r) {
         return token_mutation(t, r, numbers, 0, {"nan", "inf", "-1", "0", "99999999999999999999", "2147483648", "1e308",
                                                  "x", "", "#0", "(("});
       }},
  };
}

/// ASCII PLY: header counts, list counts, indices and coordinates.
std::vector<std::pair<const char*, Mutation>> ply_ascii_mutations() {
  const auto element = [](const std::string& l) { return starts_with(l, "element "); };
  const auto face = [](const std::string& l) { return starts_with(l, "4 "); };
  const auto vertex = [](const std::string& l) { return token_count(l) == 3 && !std::isalpha(static_cast<unsigned char>(l[0])); };
  return {
      {"truncate", truncate},
      {"delete line", delete_line},
      {"duplicate line", duplicate_line},
      {"element count",
       [=](const std::string& t, Rng& r) {
         // 1000000000, 1e9: a count the file cannot hold (issue 30: readers allocated for it first)
         return token_mutation(t, r, element, 2,
                               {"0", "1", "24", "26", "-1", "4294967295", "2147483648", "x", "1000000000", "1e9"});
       }},
      {"list count", [=](const std::string& t, Rng& r) { return token_mutation(t, r, face, 0, {"0", "3", "5", "255", "-1", "256"}); }},
      {"index out of range",
       [=](const std::string& t, Rng& r) { return token_mutation(t, r, face, 1, {"25", "-1", "2147483647", "4294967296", "1.5"}); }},
      {"non-finite coordinate", [=](const std::string& t, Rng& r) { return token_mutation(t, r, vertex, 0, kNonFinite); }},
      {"property type",
       [](const std::string& t, Rng& r) {
         return token_mutation(t, r, [](const std::string& l) { return starts_with(l, "property "); }, 1,
                               {"uchar", "list", "double", "int8", "bogus"});
       }},
      {"format",
       [](const std::string& t, Rng& r) {
         return token_mutation(t, r, [](const std::string& l) { return starts_with(l, "format "); }, 1,
                               {"binary_little_endian", "binary_big_endian", "ascii2", "2.0"});
       }},
  };
}

/// The plate of plate_4x4.ply as binary little-endian PLY (float coordinates, uchar/int lists).
std::string binary_ply_of(const std::string& ascii_ply) {
  const std::vector<std::string> lines = split_lines(ascii_ply);
  std::vector<std::array<float, 3>> v;
  std::vector<std::array<int, 4>> f;
  bool body = false;
  for (const std::string& l : lines) {
    if (!body) {
      body = l == "end_header";
      continue;
    }
    std::istringstream s(l);
    if (token_count(l) == 3) {
      std::array<float, 3> p{};
      s >> p[0] >> p[1] >> p[2];
      v.push_back(p);
    } else if (token_count(l) == 5) {
      int n = 0;
      std::array<int, 4> q{};
      s >> n >> q[0] >> q[1] >> q[2] >> q[3];
      f.push_back(q);
    }
  }
  std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(v.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(f.size()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  static_assert(std::endian::native == std::endian::little, "the binary PLY below is written in host order");
  for (const auto& p : v) out.append(reinterpret_cast<const char*>(p.data()), sizeof(float) * 3);
  for (const auto& q : f) {
    out += static_cast<char>(4);
    out.append(reinterpret_cast<const char*>(q.data()), sizeof(int) * 4);
  }
  return out;
}

std::vector<std::pair<const char*, Mutation>> ply_binary_mutations() {
  const auto body_start = [](const std::string& t) { return t.find("end_header\n") + 11; };
  return {
      {"truncate body",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         const std::size_t b = body_start(t), at = b + r.below(t.size() - b);
         return Mutant{"truncated to " + std::to_string(at) + " of " + std::to_string(t.size()) + " bytes", t.substr(0, at)};
       }},
      {"overwrite bytes",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         std::string m = t;
         const std::size_t b = body_start(t), at = b + r.below(t.size() - b), n = 1 + r.below(4);
         std::string what = "bytes from offset " + std::to_string(at) + ":";
         for (std::size_t k = at; k < std::min(at + n, m.size()); ++k) {
           const unsigned char c = static_cast<unsigned char>(r.below(256));
           m[k] = static_cast<char>(c);
           what += ' ';
           what += std::to_string(c);
         }
         return Mutant{what, m};
       }},
      {"list count",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         // faces follow 25 vertices of 12 bytes; each is a count byte and 4 ints
         const std::size_t faces = body_start(t) + 25 * 12, face = r.below(16), at = faces + face * 17;
         const std::vector<int> counts = {0, 3, 5, 255, 128};
         const int c = r.pick(counts);
         std::string m = t;
         m[at] = static_cast<char>(c);
         return Mutant{"face " + std::to_string(face) + " list count -> " + std::to_string(c), m};
       }},
      {"element count",
       [](const std::string& t, Rng& r) {
         return token_mutation(t, r, [](const std::string& l) { return starts_with(l, "element "); }, 2,
                               {"0", "24", "26", "4294967295", "100000000", "1000000000"});
       }},
      {"format",
       [](const std::string& t, Rng& r) {
         return token_mutation(t, r, [](const std::string& l) { return starts_with(l, "format "); }, 1,
                               {"ascii", "binary_big_endian"});
       }},
      {"header line deleted",
       [=](const std::string& t, Rng& r) -> std::optional<Mutant> {
         std::vector<std::string> head = split_lines(t.substr(0, body_start(t)));
         const std::size_t i = 1 + r.below(head.size() - 1);
         const std::string what = "deleted header " + quoted_line(static_cast<int>(i) + 1, head[i]);
         head.erase(head.begin() + static_cast<std::ptrdiff_t>(i));
         return Mutant{what, join_lines(head) + t.substr(body_start(t))};
       }},
  };
}

// ---- running and judging -------------------------------------------------------------------------

/// "" when the outcome is honest, else what is wrong with it.
std::string judge(const ProcResult& r, const std::string& scene, const std::vector<std::string>& sets, bool run,
                  double timeout_s) {
  if (r.timed_out) return "no exit within " + std::to_string(timeout_s) + " s (hang)";
  if (r.signal) return "killed by signal " + std::to_string(r.signal) + " (" + strsignal(r.signal) + ")";
  if (r.exit_code == 0) return "";
  if (run && (r.exit_code == 3 || r.exit_code == 4)) return "";
  if (r.exit_code != 2) return "exit " + std::to_string(r.exit_code) + " (expected 0, 2" + (run ? ", 3 or 4)" : ")");
  // exit 2: where and what
  bool at_line = false;
  for (std::size_t p = r.err.find(scene + ":"); p != std::string::npos; p = r.err.find(scene + ":", p + 1)) {
    const std::size_t d = p + scene.size() + 1;
    at_line = at_line || (d < r.err.size() && std::isdigit(static_cast<unsigned char>(r.err[d])));
  }
  bool at_set = false;
  for (const std::string& s : sets) at_set = at_set || r.err.find("--set " + s) != std::string::npos;
  // an absent table (a [table], or every [[table]] of an array) has no line to name: the file and
  // the table's key must do (tests/cli/cli_bad_input_test.cpp, missing_solver_table)
  const bool absent = r.err.find(scene + ": key '") != std::string::npos &&
                      (r.err.find("missing required table [") != std::string::npos ||
                       r.err.find(" table, got 0") != std::string::npos || r.err.find(" tables, got 0") != std::string::npos);
  if (!at_line && !at_set && !absent) return "refused (exit 2) without naming '" + scene + ":<line>:'";
  if (r.err.find("key '") == std::string::npos && r.err.find("TOML syntax error") == std::string::npos)
    return "refused (exit 2) without naming a key";
  return "";
}

/// The end that keeps a run of the scene's model to about a second, under the key's current name
/// first and its older names after (a run refused at such a --set tries the next).
std::vector<std::string> short_run_ends(const std::string& scene_text) {
  if (scene_text.find("analysis = \"static\"") != std::string::npos) return {"solver.end=0.05", "solver.lambda_end=0.05"};
  if (scene_text.find("analysis = \"dynamic\"") != std::string::npos) return {"solver.end=2e-3", "time.end=2e-3"};
  // an eigen-analysis is one step: fewer modes is its short run
  if (scene_text.find("analysis = \"modal\"") != std::string::npos) return {"modal.modes=2"};
  if (scene_text.find("analysis = \"buckling\"") != std::string::npos) return {"buckling.modes=2"};
  return {"solver.end=0.2", "solver.t_end=0.2"};
}

struct Case {
  std::string label;  ///< "seed 12, scene mutant 17 of hub_beam_fem_tau1" or "corpus file x"
  std::string what;   ///< the mutation
  std::string scene;  ///< the scene file flexframe gets
  std::string file;   ///< the mutated file (the scene, or its mesh)
};

class Fuzzer {
 public:
  explicit Fuzzer(std::string dir) : dir_(std::move(dir)) {}

  /// check (and, when `run`, a shortened run) of one case; true when honest.
  bool try_case(const Case& c, bool run = false) {
    ++count_;
    last_check_valid_ = false;
    const std::string log = dir_ + "/logs/" + std::to_string(count_);
    const ProcResult r = run_flexframe({"check", c.scene}, log + ".check", dir_, kCheckTimeout);
    if (!report(c, "check", {}, r, judge(r, c.scene, {}, false, kCheckTimeout))) return false;
    last_check_valid_ = r.exit_code == 0;
    (last_check_valid_ ? valid_ : refused_)++;
    if (!run || !last_check_valid_) return true;
    ++runs_;
    for (const std::string& end : short_run_ends(read_text(c.scene))) {
      const ProcResult rr = run_flexframe({"run", c.scene, "--out", dir_ + "/run_" + std::to_string(count_), "--no-frames",
                                           "--no-plots", "--quiet", "--set", end},
                                          log + ".run", dir_, kRunTimeout);
      if (rr.exit_code == 2 && rr.err.find("--set " + end) != std::string::npos) continue;  // not this key's name
      return report(c, "run", {end}, rr, judge(rr, c.scene, {end}, true, kRunTimeout));
    }
    ADD_FAILURE() << c.label << ": every end key of short_run_ends() was refused; update it (" << c.scene << ")";
    return false;
  }

  bool last_check_valid() const { return last_check_valid_; }
  int count() const { return count_; }
  int runs() const { return runs_; }
  int valid() const { return valid_; }
  int refused() const { return refused_; }

 private:
  bool report(const Case& c, const std::string& verb, const std::vector<std::string>& sets, const ProcResult& r,
              const std::string& problem) {
    if (problem.empty()) return true;
    std::string args = "flexframe " + verb + " " + c.scene;
    for (const std::string& s : sets) args += " --set " + s;
    ADD_FAILURE() << c.label << ": " << problem << "\n  mutation: " << c.what << "\n  mutant:   " << c.file
                  << "\n  command:  " << args << "\n  (reproduce with FF_FUZZ_SEED=" << fuzz_seed()
                  << "; keep it by copying the mutant into tests/cli/fuzz_corpus/)\n"
                  << r.describe().substr(0, 4000);
    return false;
  }

  std::string dir_;
  int count_ = 0, runs_ = 0, valid_ = 0, refused_ = 0;
  bool last_check_valid_ = false;
};

/// A test folder with `meshes`, `geometry` and `reference` beside `scenes`, so the bundled scenes'
/// relative paths (../meshes/..., ../geometry/..., ../reference/...) resolve from dir/scenes.
std::string fuzz_dir() {
  const std::string dir = fresh_test_dir();
  fs::create_directories(dir + "/scenes");
  fs::create_directories(dir + "/logs");
  fs::create_directory_symlink(std::string(FF_SOURCE_DIR) + "/assets/meshes", dir + "/meshes");
  fs::create_directory_symlink(std::string(FF_SOURCE_DIR) + "/assets/geometry", dir + "/geometry");
  fs::create_directory_symlink(std::string(FF_SOURCE_DIR) + "/assets/reference", dir + "/reference");
  return dir;
}

/// The bundled scenes as `flexframe scenes` lists them.
std::vector<std::string> listed_scenes(const std::string& dir) {
  const ProcResult r = run_flexframe({"scenes"}, dir + "/logs/scenes");
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  std::vector<std::string> names;
  for (const std::string& l : split_lines(r.out))
    if (starts_with(l, "  ")) names.push_back(trim_left(l));
  return names;
}

/// The mesh scene (clamped_plate_pressure_obj) reading `mesh` instead of its OBJ (a CAD part at
/// mesh_size 0.25).
std::string mesh_scene_text(const std::string& mesh) {
  std::string text = read_text(scene_path("clamped_plate_pressure_obj"));
  const std::string from = "\"../meshes/plate_8x8_unit.obj\"";
  const std::size_t p = text.find(from);
  EXPECT_NE(p, std::string::npos) << "clamped_plate_pressure_obj no longer reads ../meshes/plate_8x8_unit.obj";
  const std::string ext = fs::path(mesh).extension().string();
  const bool cad = ext == ".step" || ext == ".stp" || ext == ".iges" || ext == ".igs" || ext == ".brep";
  if (p != std::string::npos) text.replace(p, from.size(), "\"" + mesh + "\"" + (cad ? "\nmesh_size = 0.25" : ""));
  return text;
}

void print_tally(const Fuzzer& f, std::chrono::steady_clock::time_point start) {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("fuzz: seed %" PRIu64 ", %d mutants checked (%d valid, %d refused), %d also run, %.1f s\n", fuzz_seed(),
              f.count(), f.valid(), f.refused(), f.runs(), s);
}

// ---- the tests ----------------------------------------------------------------------------------

// Past crashers first: every file of tests/cli/fuzz_corpus/ (scenes checked as they are, meshes
// read through the mesh scene).
TEST(CliFuzz, CorpusOfPastCrashers) {
  const std::string dir = fuzz_dir();
  const fs::path corpus = fs::path(FF_SOURCE_DIR) / "tests/cli/fuzz_corpus";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(corpus))
    if (e.path().extension() != ".md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u) << "the corpus holds the crashers of issue 12";
  Fuzzer f(dir);
  for (const fs::path& p : files) {
    Case c{"corpus file " + p.filename().string(), "(as committed)", p.string(), p.string()};
    if (p.extension() != ".toml") {
      c.scene = dir + "/scenes/" + p.stem().string() + "_" + p.extension().string().substr(1) + ".toml";
      write_text(c.scene, mesh_scene_text(p.string()));
    }
    f.try_case(c);
  }
}

// Mutants of every bundled scene, round robin; some of those that still check valid also run.
TEST(CliFuzz, SceneMutants) {
  const auto start = std::chrono::steady_clock::now();
  const std::string dir = fuzz_dir();
  const std::vector<std::string> names = listed_scenes(dir);
  ASSERT_GE(names.size(), 7u);
  const int n = kSceneMutants * fuzz_scale();
  const int run_every = std::max(1, n / kRunMutants);
  Fuzzer f(dir);
  int next_run = 0;
  for (int i = 0; i < n; ++i) {
    const std::string& name = names[static_cast<std::size_t>(i) % names.size()];
    Rng rng = mutant_rng(fuzz_seed(), 1, i);
    const std::optional<Mutant> m = apply_any(scene_mutations(), read_text(scene_path(name)), rng);
    if (!m) continue;
    const std::string path = dir + "/scenes/m" + std::to_string(i) + "_" + name + ".toml";
    write_text(path, m->text);
    // a run for the first valid mutant after every run_every-th
    const bool run = i >= next_run;
    f.try_case({"seed " + std::to_string(fuzz_seed()) + ", scene mutant " + std::to_string(i) + " of " + name, m->what,
                path, path},
               run);
    if (run && f.last_check_valid()) next_run = i + run_every;
  }
  print_tally(f, start);
  // mutants that all fail the same way would test little: most must get past the parser
  EXPECT_GT(f.valid(), n / 10) << "too few mutants check valid; the mutations no longer reach the models";
  EXPECT_GT(f.runs(), 0);
}

// Mutants of quad meshes: the bundled OBJ and PLY plates and a binary PLY generated from the
// latter, each read through the mesh scene; the first valid mutant of each kind also runs.
TEST(CliFuzz, MeshMutants) {
  const auto start = std::chrono::steady_clock::now();
  const std::string dir = fuzz_dir();
  const std::string ply = read_text(std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_4x4.ply");
  const struct {
    const char* kind;
    const char* ext;
    std::string text;
    std::vector<std::pair<const char*, Mutation>> ops;
  } kinds[] = {
      {"obj", ".obj", read_text(std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_unit.obj"), obj_mutations()},
      {"ascii_ply", ".ply", ply, ply_ascii_mutations()},
      {"binary_ply", ".ply", binary_ply_of(ply), ply_binary_mutations()},
      // issue 32: files read through Gmsh (in its sandboxed child process)
      {"msh4", ".msh", read_text(std::string(FF_SOURCE_DIR) + "/tests/io/data/gmsh/square_quads_v4.msh"), text_mesh_mutations()},
      {"msh22", ".msh", read_text(std::string(FF_SOURCE_DIR) + "/tests/io/data/gmsh/square_quads_v22.msh"), text_mesh_mutations()},
      {"step", ".step", read_text(std::string(FF_SOURCE_DIR) + "/tests/io/data/gmsh/square.step"), text_mesh_mutations()},
      {"inp", ".inp", read_text(std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_s4r.inp"), text_mesh_mutations()},
  };
  Fuzzer f(dir);
  for (int k = 0; k < static_cast<int>(std::size(kinds)); ++k) {
    const auto& kind = kinds[k];
    // the unmutated mesh is valid, so refusals below come from the mutations
    const std::string base = dir + "/scenes/base_" + kind.kind + kind.ext;
    write_text(base, kind.text);
    write_text(dir + "/scenes/base_" + kind.kind + ".toml", mesh_scene_text(fs::path(base).filename().string()));
    f.try_case({std::string("unmutated ") + kind.kind, "(none)", dir + "/scenes/base_" + kind.kind + ".toml", base});
    EXPECT_TRUE(f.last_check_valid()) << "the unmutated " << kind.kind << " mesh must check valid";
    bool ran = false;
    // a file read through Gmsh costs a child process that loads Gmsh and OpenCASCADE (~0.3 s)
    const int mutants = (std::string(kind.kind).rfind("msh", 0) == 0 || std::string(kind.kind) == "step" ? kMeshMutants / 2 : kMeshMutants);
    for (int i = 0; i < mutants * fuzz_scale(); ++i) {
      Rng rng = mutant_rng(fuzz_seed(), 2 + k, i);
      const std::optional<Mutant> m = apply_any(kind.ops, kind.text, rng);
      if (!m) continue;
      const std::string stem = std::string("m") + std::to_string(i) + "_" + kind.kind;
      const std::string mesh = dir + "/scenes/" + stem + kind.ext;
      const std::string scene = dir + "/scenes/" + stem + ".toml";
      write_text(mesh, m->text);
      write_text(scene, mesh_scene_text(stem + kind.ext));
      // the first valid mutant of each kind also runs
      const int runs_before = f.runs();
      f.try_case({"seed " + std::to_string(fuzz_seed()) + ", " + kind.kind + " mutant " + std::to_string(i), m->what,
                  scene, mesh},
                 !ran);
      ran = ran || f.runs() > runs_before;
    }
  }
  print_tally(f, start);
}

}  // namespace
}  // namespace ff::cli::test
