#include <nlmech/base/json.h>

#include <deal.II/base/exceptions.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>

namespace nlmech
{
  struct JsonObject::Data
  {
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
  };

  namespace
  {
    /// The value as reported: finite, rounded to 12 significant digits (integers stay integers).
    nlohmann::ordered_json reported(const double value)
    {
      const double rounded = std::strtod(json_number(value).c_str(), nullptr);
      if (rounded == std::floor(rounded) && std::abs(rounded) < 9.0e15)
        return static_cast<long long>(rounded);
      return rounded;
    }

    /// One line: figures {"value": v, "unit": u}, lists, strings and numbers.
    std::string inline_text(const nlohmann::ordered_json &j)
    {
      std::string out;
      if (j.is_object())
        {
          out = "{";
          for (auto it = j.begin(); it != j.end(); ++it)
            out += (it == j.begin() ? "" : ", ") + nlohmann::ordered_json(it.key()).dump() + ": " +
                   inline_text(it.value());
          return out + "}";
        }
      if (j.is_array())
        {
          out = "[";
          for (std::size_t i = 0; i < j.size(); ++i)
            out += (i ? ", " : "") + inline_text(j[i]);
          return out + "]";
        }
      return j.dump();
    }

    bool is_figure(const nlohmann::ordered_json &j)
    {
      return j.is_object() && j.size() == 2 && j.contains("value") && j.contains("unit");
    }

    /// Objects one entry per line, indented by two per level; figures and lists on one line.
    void print(const nlohmann::ordered_json &j, const unsigned int indent, std::string &out)
    {
      if (!j.is_object() || j.empty() || is_figure(j))
        {
          out += inline_text(j);
          return;
        }
      out += "{\n";
      const std::string pad(indent + 2, ' ');
      for (auto it = j.begin(); it != j.end(); ++it)
        {
          out += pad + nlohmann::ordered_json(it.key()).dump() + ": ";
          print(it.value(), indent + 2, out);
          out += std::next(it) == j.end() ? "\n" : ",\n";
        }
      out += std::string(indent, ' ') + "}";
    }
  } // namespace

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
    return nlohmann::ordered_json(text).dump();
  }

  JsonObject::JsonObject()
      : data(std::make_unique<Data>())
  {
  }

  JsonObject::JsonObject(const JsonObject &other)
      : data(std::make_unique<Data>(*other.data))
  {
  }

  JsonObject &JsonObject::operator=(const JsonObject &other)
  {
    *data = *other.data;
    return *this;
  }

  JsonObject::~JsonObject() = default;

  bool JsonObject::empty() const
  {
    return data->object.empty();
  }

  void JsonObject::add_figure(const std::string &key, double value, const std::string &unit)
  {
    data->object[key] = {{"value", reported(value)}, {"unit", unit}};
  }

  void JsonObject::add_number(const std::string &key, double value)
  {
    data->object[key] = reported(value);
  }

  void JsonObject::add_string(const std::string &key, const std::string &value)
  {
    data->object[key] = value;
  }

  void JsonObject::add_bool(const std::string &key, bool value)
  {
    data->object[key] = value;
  }

  void JsonObject::add_object(const std::string &key, const JsonObject &object)
  {
    data->object[key] = object.data->object;
  }

  void JsonObject::add_numbers(const std::string &key, const std::vector<double> &values)
  {
    auto list = nlohmann::ordered_json::array();
    for (const double v : values)
      list.push_back(reported(v));
    data->object[key] = list;
  }

  void JsonObject::add_strings(const std::string &key, const std::vector<std::string> &values)
  {
    data->object[key] = values;
  }

  std::string JsonObject::to_string(unsigned int indent) const
  {
    std::string out;
    print(data->object, indent, out);
    return out;
  }
} // namespace nlmech
