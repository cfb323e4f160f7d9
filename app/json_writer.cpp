#include "app/json_writer.h"

#include <cmath>
#include <cstdio>

namespace ff::app {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

JsonObject& JsonObject::add(const std::string& key, const std::vector<std::string>& values) {
  std::string a = "[";
  for (std::size_t i = 0; i < values.size(); ++i) a += (i ? ", " : "") + json_string(values[i]);
  return raw(key, a + "]");
}

JsonObject& JsonObject::raw(const std::string& key, const std::string& json) {
  items_.emplace_back(key, json);
  return *this;
}

std::string JsonObject::str(int indent) const {
  const std::string pad(indent + 2, ' '), end(indent, ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < items_.size(); ++i) {
    std::string value = items_[i].second;
    // re-indent nested objects
    std::string nested;
    for (char c : value) {
      nested += c;
      if (c == '\n') nested += std::string(indent + 2, ' ');
    }
    out += pad + json_string(items_[i].first) + ": " + nested + (i + 1 < items_.size() ? ",\n" : "\n");
  }
  return out + end + "}";
}

}  // namespace ff::app
