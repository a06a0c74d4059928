// JSON text for the reports: strings escaped, non-finite numbers as null, lists and objects.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace sdp::json {

inline std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

// JSON has no inf/nan: a non-finite number is written as null.
inline std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

inline std::string jsonInt(int x) {
  return std::to_string(x);
}

template <class T>
inline std::string jsonList(const std::vector<T>& items, std::string (*item)(const T&)) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + item(items[i]);
  return out + "]";
}

// {"a": 1, "b": 2} from key/value-text pairs.
inline std::string jsonObject(const std::vector<std::pair<std::string, std::string>>& members) {
  std::string out = "{";
  for (size_t i = 0; i < members.size(); ++i)
    out += (i ? ", " : "") + jsonString(members[i].first) + ": " + members[i].second;
  return out + "}";
}

// {"a": 1.5, "b": 2} from keys and numbers, in their order (a report's stage seconds or work).
inline std::string jsonNumbers(const std::vector<std::pair<std::string, double>>& members) {
  std::vector<std::pair<std::string, std::string>> text;
  for (const auto& [key, value] : members) text.emplace_back(key, jsonNumber(value));
  return jsonObject(text);
}

}  // namespace sdp::json
