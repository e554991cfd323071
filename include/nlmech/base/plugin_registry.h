#pragma once
// A registry of plugins of one interface, filled at load time (ASPECT-style): each plugin has a
// name, a one-line description, the functions that declare its parameters and a factory that
// parses them. Plugins sharing a parameter group list the same declare function, which the
// registry calls once.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace nlmech
{
  template <class Interface>
  struct PluginInfo
  {
    using Declare = void (*)(dealii::ParameterHandler &);
    std::string                                                           name;
    std::string                                                           description;
    std::vector<Declare>                                                  declare_parameters;
    std::function<std::unique_ptr<Interface>(dealii::ParameterHandler &)> create; // parses and checks
  };

  template <class Interface>
  class PluginRegistry
  {
  public:
    using Info = PluginInfo<Interface>;

    static PluginRegistry &instance()
    {
      static PluginRegistry registry;
      return registry;
    }

    void add(const Info &info)
    {
      AssertThrow(!has(info.name), dealii::ExcMessage("Plugin <" + info.name + "> registered twice."));
      registered.push_back(info);
      std::sort(registered.begin(), registered.end(),
                [](const Info &a, const Info &b) { return a.name < b.name; });
    }

    bool has(const std::string &name) const
    {
      return std::any_of(registered.begin(), registered.end(), [&](const Info &p) { return p.name == name; });
    }

    /// Throws with the list of valid names when `name` is not registered.
    const Info &get(const std::string &name) const
    {
      for (const auto &p : registered)
        if (p.name == name)
          return p;
      AssertThrow(false, dealii::ExcMessage("Unknown kind <" + name +
                                            ">. Registered: " + names_separated_by(", ") + "."));
      return registered.front();
    }

    const std::vector<Info> &plugins() const { return registered; }

    std::string names_separated_by(const std::string &separator) const
    {
      std::string out;
      for (std::size_t i = 0; i < registered.size(); ++i)
        out += (i ? separator : "") + registered[i].name;
      return out;
    }

    /// Declares the parameters of every plugin, each shared group once, in the current subsection.
    void declare_parameters(dealii::ParameterHandler &prm) const
    {
      std::vector<typename Info::Declare> done;
      for (const auto &p : registered)
        for (const auto declare : p.declare_parameters)
          if (std::find(done.begin(), done.end(), declare) == done.end())
            {
              declare(prm);
              done.push_back(declare);
            }
    }

  private:
    std::vector<Info> registered;
  };

  template <class Interface>
  struct PluginRegistration
  {
    explicit PluginRegistration(const PluginInfo<Interface> &info)
    {
      PluginRegistry<Interface>::instance().add(info);
    }
  };
} // namespace nlmech
