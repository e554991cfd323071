#pragma once
// One biphasic-sheet scheme's run (energy rows, figures, messages, the largest stretch per
// direction), packed into a string of length-prefixed fields for the gather to rank 0.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace nlmech
{
  struct SchemeOutcome
  {
    struct Figure
    {
      std::string name;
      double      value;
      std::string unit;
    };
    std::size_t         index = 0;
    std::string         csv, message, error;
    std::vector<Figure> figures;
    std::vector<double> reached;       // largest stretch per grid direction over the run
    std::string         check_failure; // the curve was not held to its tolerance

    static void put(std::string &out, const std::string &field)
    {
      out += std::to_string(field.size()) + ":" + field;
    }
    static std::string take(const std::string &in, std::size_t &pos)
    {
      const std::size_t colon = in.find(':', pos);
      const std::size_t n     = std::stoul(in.substr(pos, colon - pos));
      std::string       field = in.substr(colon + 1, n);
      pos                     = colon + 1 + n;
      return field;
    }
    void pack(std::string &out) const
    {
      put(out, std::to_string(index)), put(out, csv), put(out, message), put(out, error);
      put(out, check_failure);
      char value[64];
      put(out, std::to_string(reached.size()));
      for (const double r : reached)
        {
          std::snprintf(value, sizeof value, "%.17g", r);
          put(out, value);
        }
      put(out, std::to_string(figures.size()));
      for (const auto &f : figures)
        {
          std::snprintf(value, sizeof value, "%.17g", f.value);
          put(out, f.name), put(out, value), put(out, f.unit);
        }
    }
    static SchemeOutcome unpack(const std::string &in, std::size_t &pos)
    {
      SchemeOutcome o;
      o.index             = std::stoul(take(in, pos));
      o.csv               = take(in, pos);
      o.message           = take(in, pos);
      o.error             = take(in, pos);
      o.check_failure     = take(in, pos);
      const std::size_t m = std::stoul(take(in, pos));
      for (std::size_t k = 0; k < m; ++k)
        o.reached.push_back(std::strtod(take(in, pos).c_str(), nullptr));
      const std::size_t n = std::stoul(take(in, pos));
      for (std::size_t k = 0; k < n; ++k)
        {
          Figure f;
          f.name  = take(in, pos);
          f.value = std::strtod(take(in, pos).c_str(), nullptr);
          f.unit  = take(in, pos);
          o.figures.push_back(f);
        }
      return o;
    }
  };

} // namespace nlmech
