#include <nlmech/base/json.h>

#include <deal.II/base/exceptions.h>

#include <cmath>
#include <cstdio>

namespace nlmech
{
  std::string json_number(double value)
  {
    AssertThrow(std::isfinite(value),
                dealii::ExcMessage("Refusing to write a non-finite number (NaN or inf) to a result."));
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.12g", value);
    return buffer;
  }

  std::string json_quote(const std::string &text)
  {
    std::string out = "\"";
    for (char c : text)
      switch (c)
        {
          case '"': out += "\\\""; break;
          case '\\': out += "\\\\"; break;
          case '\n': out += "\\n"; break;
          case '\t': out += "\\t"; break;
          default: out += c;
        }
    return out + "\"";
  }

  void JsonObject::add_figure(const std::string &key, double value, const std::string &unit)
  {
    entries.emplace_back(key, "{\"value\": " + json_number(value) + ", \"unit\": " + json_quote(unit) + "}");
  }

  void JsonObject::add_number(const std::string &key, double value)
  {
    entries.emplace_back(key, json_number(value));
  }

  void JsonObject::add_string(const std::string &key, const std::string &value)
  {
    entries.emplace_back(key, json_quote(value));
  }

  void JsonObject::add_bool(const std::string &key, bool value)
  {
    entries.emplace_back(key, value ? "true" : "false");
  }

  void JsonObject::add_object(const std::string &key, const JsonObject &object)
  {
    // Stored by reference so that it is indented where it is printed.
    nested.emplace_back(object);
    entries.emplace_back(key, "\x01" + std::to_string(nested.size() - 1));
  }

  void JsonObject::add_numbers(const std::string &key, const std::vector<double> &values)
  {
    std::string list = "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      list += (i ? ", " : "") + json_number(values[i]);
    entries.emplace_back(key, list + "]");
  }

  void JsonObject::add_strings(const std::string &key, const std::vector<std::string> &values)
  {
    std::string list = "[";
    for (std::size_t i = 0; i < values.size(); ++i)
      list += (i ? ", " : "") + json_quote(values[i]);
    entries.emplace_back(key, list + "]");
  }

  std::string JsonObject::to_string(unsigned int indent) const
  {
    const std::string pad(indent + 2, ' ');
    std::string       out = "{\n";
    for (std::size_t i = 0; i < entries.size(); ++i)
      {
        out += pad + json_quote(entries[i].first) + ": ";
        if (!entries[i].second.empty() && entries[i].second[0] == '\x01')
          out += nested[std::stoul(entries[i].second.substr(1))].to_string(indent + 2);
        else
          out += entries[i].second;
        out += (i + 1 < entries.size() ? ",\n" : "\n");
      }
    return out + std::string(indent, ' ') + "}";
  }
} // namespace nlmech
