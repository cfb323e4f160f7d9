#include "core/scene/schema_text.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace ff::scene::text {

std::string number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  if (ec != std::errc()) return std::to_string(x);
  return std::string(buf, end);
}

std::string toml_number(double x) {
  std::string s = number(x);
  if (std::isfinite(x) && s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string quoted(std::string_view s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string clip(std::string_view s, std::size_t max) {
  if (s.size() <= max) return std::string(s);
  return std::string(s.substr(0, max)) + "...";
}

std::string join(const std::vector<std::string>& items, std::string_view sep) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}

std::string toml_value(const Value& v) {
  struct Visitor {
    std::string operator()(std::monostate) const { return ""; }
    std::string operator()(double x) const { return toml_number(x); }
    std::string operator()(long long x) const { return std::to_string(x); }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(const std::string& s) const { return quoted(s); }
    std::string operator()(const std::vector<double>& xs) const {
      std::vector<std::string> parts;
      for (double x : xs) parts.push_back(toml_number(x));
      return bracketed(parts);
    }
    std::string operator()(const std::vector<std::string>& ss) const {
      std::vector<std::string> parts;
      for (const auto& s : ss) parts.push_back(quoted(s));
      return bracketed(parts);
    }
    static std::string bracketed(const std::vector<std::string>& parts) {
      std::string out = "[";
      out += join(parts, ", ");
      return out + "]";
    }
  };
  return std::visit(Visitor{}, v);
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  const std::size_t n = a.size(), m = b.size();
  // d[i][j] = distance between a[0..i) and b[0..j)
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  // a typo costs about one edit per three characters; never suggest a word that shares
  // less than half its letters with the input
  const std::size_t budget = std::max<std::size_t>(1, word.size() / 3);
  std::string best;
  std::size_t best_d = budget + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d && 2 * d <= c.size()) {
      best = c;
      best_d = d;
    }
  }
  if (!best.empty()) return best;
  // a word cut short is a plausible typo too ('clamp' for 'clamped'): at least 3 letters and
  // at least half of the candidate; the shortest such candidate wins
  if (word.size() < 3) return best;
  auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  for (const auto& c : candidates) {
    if (c.size() <= word.size() || 2 * word.size() < c.size()) continue;
    if (!std::equal(word.begin(), word.end(), c.begin(),
                    [&](char x, char y) { return lower(x) == lower(y); }))
      continue;
    if (best.empty() || c.size() < best.size()) best = c;
  }
  return best;
}

std::string kind_noun(Kind kind) {
  switch (kind) {
    case Kind::Number: return "a number";
    case Kind::Integer: return "an integer";
    case Kind::Boolean: return "a boolean (true or false)";
    case Kind::String: return "a string";
    case Kind::Choice: return "a string";
    case Kind::NumberList: return "a list of numbers";
    case Kind::StringList: return "a list of strings";
  }
  return "a value";
}

std::vector<std::string> split_trimmed(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, sep);) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    out.push_back(item);
  }
  return out;
}

bool parse_finite(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(*v);
}

}  // namespace ff::scene::text
