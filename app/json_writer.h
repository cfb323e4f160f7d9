#pragma once
/// Minimal JSON output for summary.json and bench results (numbers as %.17g, NaN/inf as null).
#include <sstream>
#include <string>
#include <vector>

namespace ff::app {

std::string json_string(const std::string& s);
std::string json_number(double v);

/// Builds one JSON object, keys in insertion order.
class JsonObject {
 public:
  JsonObject& add(const std::string& key, const std::string& value) { return raw(key, json_string(value)); }
  JsonObject& add(const std::string& key, const char* value) { return raw(key, json_string(value)); }
  JsonObject& add(const std::string& key, double value) { return raw(key, json_number(value)); }
  JsonObject& add(const std::string& key, long long value) { return raw(key, std::to_string(value)); }
  JsonObject& add(const std::string& key, int value) { return raw(key, std::to_string(value)); }
  JsonObject& add(const std::string& key, bool value) { return raw(key, value ? "true" : "false"); }
  JsonObject& add(const std::string& key, const std::vector<std::string>& values);
  JsonObject& add(const std::string& key, const JsonObject& object) { return raw(key, object.str()); }
  JsonObject& raw(const std::string& key, const std::string& json);
  std::string str(int indent = 0) const;

 private:
  std::vector<std::pair<std::string, std::string>> items_;
};

}  // namespace ff::app
