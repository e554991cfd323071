#pragma once
// summary.json's ordered object of named figures with units, written by nlohmann::json (the
// header stays free of it: the object lives behind a pointer). Numbers are kept to 12 significant
// digits, as the results have always been reported; non-finite numbers are refused.

#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  class JsonObject
  {
  public:
    JsonObject();
    JsonObject(const JsonObject &other);
    JsonObject &operator=(const JsonObject &other);
    ~JsonObject();

    /// A figure with its unit: "key": {"value": v, "unit": "m"}. Non-finite values are refused.
    void add_figure(const std::string &key, double value, const std::string &unit);
    void add_number(const std::string &key, double value);
    void add_string(const std::string &key, const std::string &value);
    void add_bool(const std::string &key, bool value);
    void add_object(const std::string &key, const JsonObject &object);
    void add_numbers(const std::string &key, const std::vector<double> &values);
    void add_strings(const std::string &key, const std::vector<std::string> &values);

    /// The object, pretty-printed with two spaces per level (`indent`: the first level's offset).
    std::string to_string(unsigned int indent = 0) const;
    bool        empty() const;

  private:
    struct Data;
    std::unique_ptr<Data> data;
  };

  /// A finite number for CSV and JSON text, 12 significant digits; throws for NaN and inf.
  std::string json_number(double value);
  std::string json_quote(const std::string &text);
} // namespace nlmech
