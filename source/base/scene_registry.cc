#include <nlmech/base/scene.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace nlmech
{
  SceneRegistry &SceneRegistry::instance()
  {
    static SceneRegistry registry;
    return registry;
  }

  void SceneRegistry::add(const SceneInfo &info)
  {
    AssertThrow(!has(info.name), dealii::ExcMessage("Scene <" + info.name + "> registered twice."));
    registered.push_back(info);
    std::sort(registered.begin(), registered.end(),
              [](const SceneInfo &a, const SceneInfo &b) { return a.name < b.name; });
  }

  bool SceneRegistry::has(const std::string &name) const
  {
    return std::any_of(registered.begin(), registered.end(),
                       [&](const SceneInfo &s) { return s.name == name; });
  }

  const SceneInfo &SceneRegistry::get(const std::string &name) const
  {
    for (const auto &s : registered)
      if (s.name == name)
        return s;
    AssertThrow(false, dealii::ExcMessage("Unknown scene <" + name +
                                          ">. Registered scenes: " + names_separated_by(", ") + "."));
    return registered.front();
  }

  std::string SceneRegistry::names_separated_by(const std::string &separator) const
  {
    std::string out;
    for (std::size_t i = 0; i < registered.size(); ++i)
      out += (i ? separator : "") + registered[i].name;
    return out;
  }
} // namespace nlmech
