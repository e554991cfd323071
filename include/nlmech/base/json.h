#pragma once
// A small ordered JSON object writer for summary.json: named figures with units.

#include <string>
#include <utility>
#include <vector>

namespace nlmech
{
  class JsonObject
  {
  public:
    /// A figure with its unit: "key": {"value": v, "unit": "m"}. Non-finite values are refused.
    void add_figure(const std::string &key, double value, const std::string &unit);
    void add_number(const std::string &key, double value);
    void add_string(const std::string &key, const std::string &value);
    void add_bool(const std::string &key, bool value);
    void add_object(const std::string &key, const JsonObject &object);
    void add_numbers(const std::string &key, const std::vector<double> &values);
    void add_strings(const std::string &key, const std::vector<std::string> &values);

    std::string to_string(unsigned int indent = 0) const;
    bool        empty() const { return entries.empty(); }

  private:
    std::vector<std::pair<std::string, std::string>> entries; // key, serialized value
    std::vector<JsonObject>                          nested;  // objects, referenced from entries
  };

  std::string json_number(double value);
  std::string json_quote(const std::string &text);
} // namespace nlmech
